#include "machine/local_memory.h"

#include <cstring>

namespace rtm {

LocalMemory::LocalMemory(sc_core::sc_module_name name, PeContext& ctx, size_t pixels)
    : sc_module(name), frame(pixels), ids(pixels, -1), ctx_(ctx) {
  socket.register_b_transport(this, &LocalMemory::b_transport);
}

void LocalMemory::b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time&) {
  const uint64_t addr = t.get_address();
  const size_t len = t.get_data_length();
  t.set_response_status(tlm::TLM_OK_RESPONSE);
  if (t.is_write() && addr == kSceneBase) {
    SceneImageExtension* ext = nullptr;
    t.get_extension(ext);
    if (!ext || !ext->image) return t.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);
    ctx_.image = ext->image;
  } else if (t.is_write() && addr == kRayBase && len % sizeof(Ray) == 0) {
    const size_t n = len / sizeof(Ray);
    const size_t old = rays.size();
    rays.resize(old + n);
    std::memcpy(static_cast<void*>(rays.data() + old), t.get_data_ptr(), len);
    rays_arrived.notify(sc_core::SC_ZERO_TIME);
  } else if (t.is_read() && addr == kFrameBase && len == frame.size() * sizeof(PixelSum)) {
    std::memcpy(t.get_data_ptr(), frame.data(), len);
  } else if (t.is_read() && addr == kIdBase && len == ids.size() * sizeof(int32_t)) {
    std::memcpy(t.get_data_ptr(), ids.data(), len);
  } else {
    t.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
  }
}

}  // namespace rtm

namespace rtm {

SceneImage::SceneImage(const Scene& s, const Grid& g, const MachineConfig& c)
    : scene(&s), grid(&g), mem32(s, g, c.recentre, c.numerics()), mem64(s, g, c.recentre, c.numerics()) {
  const bool sparse = c.mac_schedule == MachineConfig::MacSchedule::Sparse;
  if (sparse) {
    mem32.use_sparse_schedule();
    mem64.use_sparse_schedule();
  }
  // The bytes a PE's local memory holds, in the machine's word size: per primitive its
  // coefficient RAM words (13; with sparse schedules only the non-zero ones plus a mask word),
  // 3 for its centre, 4 per clip half-space, 6 for its bounds and one for its material; the
  // voxel data (one offset per voxel plus one id per reference); per light 6 words, per
  // material 8.
  const bool fp32 = c.precision == Precision::Fp32;
  const uint64_t word = fp32 ? 4 : 8;
  uint64_t words = 0;
  for (size_t i = 0; i < s.primitives.size(); ++i) {
    uint64_t ram = kRamWords;
    if (sparse) {
      ram = 1;
      for (int w = 0; w < kRamWords; ++w) ram += (fp32 ? mem32.rams[i][size_t(w)] : mem64.rams[i][size_t(w)]) != 0;
    }
    words += ram + 3 + 4 * s.primitives[i].clips.size() + 6 + 1;
  }
  words += 6 * s.lights.size() + 8 * s.materials.size();
  bytes = words * word + 4 * (g.start.size() + g.items.size());
}

}  // namespace rtm
