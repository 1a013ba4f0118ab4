// A PE's local memory as a TLM-2.0 target: the host writes the scene image and the PE's primary
// rays into it, and reads the PE's frame buffer back. With partition = dynamic the rays come a
// tile at a time, each the answer to the PE's request for one, and the frame buffer grows with
// them: its slots are the rays' places, in the order they came.
#pragma once

#include <functional>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include "machine/pe_context.h"
#include "render/pixel_sum.h"

namespace rtm {

/// Carries the scene image on a write to kSceneBase. Every PE gets an identical copy, so the
/// simulator shares one read-only image; the transfer is timed by its true byte count.
struct SceneImageExtension : tlm::tlm_extension<SceneImageExtension> {
  std::shared_ptr<const SceneImage> image;
  tlm::tlm_extension_base* clone() const override { return new SceneImageExtension(*this); }
  void copy_from(const tlm::tlm_extension_base& e) override {
    image = static_cast<const SceneImageExtension&>(e).image;
  }
};

class LocalMemory : public sc_core::sc_module {
 public:
  static constexpr uint64_t kSceneBase = 0x0000'0000;
  static constexpr uint64_t kRayBase = 0x1000'0000;    ///< primary rays, appended in arrival order
  static constexpr uint64_t kFrameBase = 0x2000'0000;  ///< frame buffer (PixelSum per pixel slot)
  static constexpr uint64_t kIdBase = 0x3000'0000;  ///< primary-hit primitive ids (int32 per slot)
  /// partition = dynamic: the host's answer that no tile is left (a descriptor of height 0).
  static constexpr uint64_t kNoTileBase = 0x4000'0000;

  tlm_utils::simple_target_socket<LocalMemory> socket{"socket"};

  LocalMemory(sc_core::sc_module_name name, PeContext& ctx, size_t pixels);

  // Primary rays as they arrive from the host.
  std::vector<Ray> rays;
  size_t rays_expected = 0;  ///< kRaysUnknown: more may come (partition = dynamic)
  size_t transfers_in = 0;   ///< writes of rays, or of the answer that no tile is left
  sc_core::sc_event rays_arrived;
  /// partition = dynamic: the PE's request for its next tile, to the host (set by the machine).
  std::function<void()> ask_for_tile;
  /// frames > 1: the PE has ended a frame, more to come, now (the host is told: tell_frame_end,
  /// set by the machine).
  void frame_ended() {
    ++frames_ended_;
    if (tell_frame_end) tell_frame_end();
  }
  std::function<void()> tell_frame_end;
  /// frames > 1: the frames the PE has ended so far.
  size_t frames_ended() const { return frames_ended_; }
  // The PE's part of the frame, indexed by pixel slot.
  std::vector<PixelSum> frame;
  std::vector<int32_t> ids;

 private:
  void b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time& delay);
  PeContext& ctx_;
  size_t frames_ended_ = 0;
};

}  // namespace rtm
