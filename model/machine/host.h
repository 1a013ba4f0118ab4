// The host (paper §3.2): voxel-data generation and primary-ray generation, then the transfer of
// the scene and each PE's primary rays into the PEs' local memories over the host-PE link
// (TLM-2.0 b_transport, timed by bytes, bandwidth and latency), and at the end the gathering
// of the PEs' frame buffers.
#pragma once

#include <memory>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include "machine/pe.h"
#include "units/memory_layout.h"

namespace rtm {

/// When each phase of the frame ended.
struct HostTimes {
  sc_core::sc_time voxels, rays, transfer, pes_done, gathered;
  sc_core::sc_time link_busy = sc_core::SC_ZERO_TIME;
};

class Host : public sc_core::sc_module {
 public:
  std::vector<std::unique_ptr<tlm_utils::simple_initiator_socket<Host>>> links;  ///< one per PE

  SC_HAS_PROCESS(Host);
  Host(sc_core::sc_module_name name, const MachineConfig& c, const Scene& s, const Grid& g,
       std::shared_ptr<const SceneImage> image, std::vector<std::vector<uint32_t>> parts, std::vector<Pe*> pes,
       Timekeeper* keeper);

  HostTimes times;
  Image image;  ///< the gathered frame
  bool done = false;
  sc_core::sc_time busy_until = sc_core::SC_ZERO_TIME;  ///< the host's current work ends then (for stall detection)

 private:
  void run();
  void transfer(int pe, tlm::tlm_command cmd, uint64_t addr, unsigned char* data, size_t len, uint64_t timed_bytes,
                SceneImageExtension* ext = nullptr);
  sc_core::sc_time link_time(uint64_t bytes) const;
  void host_wait(sc_core::sc_time t);

  MachineConfig config_;
  const Scene& scene_;
  const Grid& grid_;
  std::shared_ptr<const SceneImage> image_;
  std::vector<std::vector<uint32_t>> parts_;
  std::vector<Pe*> pes_;
  Sleeper sleep_;  ///< rank 0: the host goes first in its cycle
};


}  // namespace rtm
