// The host (paper §3.2): voxel-data generation and primary-ray generation, then the transfer of
// the scene and each PE's primary rays into the PEs' local memories over the interconnect
// (TLM-2.0 b_transport, timed by net/interconnect.h: topology, bytes, bandwidth, latency), and
// the gathering of the PEs' frame buffers. With partition = dynamic it deals the screen's tiles
// to the PEs as they ask for them (frame/tiles.h), one up front to each. With frames > 1 it
// prepares and sends frame after frame, each as soon as every PE has finished the frame two
// before (each local memory holds two frames' scenes, rays and frame buffers), and puts each
// frame's pixels on the links as the PEs end it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include "frame/machine_result.h"
#include "frame/tiles.h"
#include "machine/pe.h"
#include "net/interconnect.h"
#include "memory/memory_layout.h"

namespace rtm {

/// A PE's build of its voxel data (voxelisation = pe), in ticks of simulated time.
uint64_t pe_voxelisation_ticks(const MachineConfig& c, const Grid& g);

class Host : public sc_core::sc_module {
 public:
  /// One per PE: the logical path from the host to its local memory, whatever links the
  /// interconnect routes it over (their timing is net_'s).
  std::vector<std::unique_ptr<tlm_utils::simple_initiator_socket<Host>>> links;

  SC_HAS_PROCESS(Host);
  Host(sc_core::sc_module_name name, const MachineConfig& c, const Scene& s, const Grid& g,
       std::shared_ptr<const SceneImage> image, std::vector<std::vector<uint32_t>> parts,
       std::vector<Pe*> pes, Timekeeper* keeper);

  HostTimes times;
  Image image;  ///< the gathered frame
  bool done = false;
  sc_core::sc_time busy_until =
      sc_core::SC_ZERO_TIME;  ///< the host's current work ends then (for stall detection)
  /// The links' use over the frame (topology's names, busy times and bytes).
  const std::vector<LinkUse>& link_use() const { return net_.links(); }
  /// One PE's copy of the scene as the link carries it: without the voxel data when the PEs build
  /// it (voxelisation = pe).
  uint64_t scene_link_bytes() const;
  /// partition = dynamic: PE `pe` asks for its next tile, now (from the PE's process).
  void ask_for_tile(int pe);
  /// partition = dynamic: the tiles each PE got.
  std::vector<uint32_t> tiles_per_pe() const;
  /// frames > 1: PE `pe` has ended a frame, more to come, now (from the PE's process).
  void pe_frame_ended(int pe);

 private:
  /// A b_transport into PE `pe`'s local memory, at once.
  void transport(int pe, tlm::tlm_command cmd, uint64_t addr, unsigned char* data, size_t len,
                 sc_core::sc_time delay, SceneImageExtension* ext = nullptr);
  /// Carries out `deliver` (a write into a PE) when the transfer's data arrives there: now, or
  /// when the host's clock passes that time (host_sleep_until).
  void deliver_at(uint64_t arrive, std::function<void()> deliver);
  /// Sleeps until `t`, carrying out on the way the deliveries due before it.
  void host_sleep_until(uint64_t t);
  /// After asking the interconnect for a transfer: on until one of the host's ports is free.
  void wait_for_a_port();
  /// The host's own work for `t`, counted in times.work.
  void host_work(sc_core::sc_time t);
  /// The host's thread: pre-processing, then every PE's data, then the gather.
  void run();
  sc_core::sc_time host_cycle() const;
  /// The host's change of frame (pe_frame = grid) of `items` primitives, lights and cameras.
  void frame_work(uint64_t items);
  /// The host's voxel-data generation: host_voxel_cycles a primitive reference.
  void voxel_work();
  /// `cycles` PE cycles in ticks, `what` naming them if they pass the time horizon.
  uint64_t pe_ticks(uint64_t cycles, const char* what) const;
  void preprocess();
  /// scene_block > 0: pre-processing and the scene's transfer a block of primitives at a time,
  /// each block sent while the host frames the next, the PEs registering each block's references
  /// as it arrives (voxelisation = pe).
  void stream_scene();
  /// One block of the scene to every PE (broadcast, or a copy each): its times at each PE.
  std::vector<TransferTimes> send_scene_block(uint64_t bytes);
  /// Sends every PE its scene and primary rays, all at once or block by block (ray_block).
  void distribute();
  /// PE `pe`'s primary rays `from`.. (`count` of them, fewer at the end of its pixels).
  std::vector<Ray> rays_of(int pe, size_t from, size_t count) const;
  /// A transfer of PE `pe`'s primary rays, no earlier than `ready` (`first`: the PE's first):
  /// when it lands in the PE's memory, and the write that lands it.
  std::pair<uint64_t, std::function<void()>> ray_write(int pe, std::vector<Ray> rays,
                                                       uint64_t ready, bool first);
  void send_rays(int pe, std::vector<Ray> rays);
  void deliver_scene(int pe, const TransferTimes& t);
  /// Writes the scene into PE `pe`'s memory as transfer `t` (its last part) arrives.
  void write_scene(int pe, const TransferTimes& t);
  void send_scene(int pe);
  void send_scene_to_all();
  /// Reads PE `pe`'s frame buffer into the image, the transport taking `delay`.
  void read_frame(int pe, sc_core::sc_time delay);
  /// Gathers PE `pe`'s frame buffer in one transfer.
  void gather(int pe);
  /// Every PE's frame buffer in blocks sent as their pixels finish (gather = streamed).
  void gather_streamed();
  /// Gathers every PE's frame buffer: after all are done, each as it finishes, or streamed
  /// (gather).
  void gather_all();
  /// frames > 1: the frames every PE with pixels has ended (its local memory counts them).
  size_t frames_ended_by_all() const;
  /// frames > 1: until every PE has ended frame `k` (counted from 0), landing the writes due
  /// meanwhile.
  void wait_for_frame(size_t k);
  /// frames > 1: PE `pe`'s part of frame `k` onto the links, each transfer in the first gap after
  /// it is ready that the transfers asked for so far leave: the whole part from `ready` on, or
  /// (gather = streamed) each block once its pixels are done.
  void gather_frame(int pe, size_t k, uint64_t ready);
  /// frames > 1: once every PE is done, the last frame's parts (the others went as the PEs ended
  /// them: pe_frame_ended), and every frame's pixels read.
  void gather_frames();
  /// partition = dynamic: sends PE `pe` tile `k` (its rays, or its descriptor) or, without one,
  /// the answer that none is left, no earlier than `ready`; returns when it lands in the PE's
  /// memory and the write that lands it.
  std::pair<uint64_t, std::function<void()>> send_tile(int pe, std::optional<size_t> k,
                                                       uint64_t ready, bool first);
  /// partition = dynamic: the host's tile dealer, a process of its own beside the host's thread:
  /// takes the PEs' requests as they are made, answers them in the order they arrive (of equal
  /// times, by PE), and lands the answers in the PEs' memories.
  void deal_tiles();

  MachineConfig config_;
  const Scene& scene_;
  const Grid& grid_;
  std::shared_ptr<const SceneImage> image_;
  std::vector<std::vector<uint32_t>> parts_;
  std::vector<Pe*> pes_;
  std::vector<uint64_t> scene_ready_;  ///< per PE: its scene copy whole in local memory from then
  Sleeper sleep_;                      ///< rank 0: the host goes first in its cycle
  Interconnect net_;
  /// Writes issued for later (a star's or a tree's link still busy), by arrival, then issue order.
  std::multimap<uint64_t, std::function<void()>> pending_;
  // partition = dynamic.
  std::vector<Tile> tiles_;
  TileDealer dealer_{0};
  struct Ask {
    uint64_t at;  ///< made (asked_), or arrived at the host (arrived_)
    int pe;
    bool operator<(const Ask& o) const { return at != o.at ? at < o.at : pe < o.pe; }
  };
  std::vector<Ask> asked_, arrived_;
  std::multimap<uint64_t, std::function<void()>> answers_;  ///< the dealer's writes, by arrival
  Sleeper deal_sleep_;                                      ///< rank 0, as the host's
  sc_core::sc_event asked_event_;  ///< arbitration = kernel: a request was made
  // frames > 1.
  sc_core::sc_event frame_ended_event_;
  Sleeper frame_sleep_;  ///< rank 0, as the host's: the waits for a frame's end
};

}  // namespace rtm
