#include "machine/local_memory.h"

#include <cstring>

namespace rtm {

LocalMemory::LocalMemory(sc_core::sc_module_name name, PeContext& ctx, size_t pixels)
    : sc_module(name), frame(pixels), ids(pixels, -1), ctx_(ctx) {
  socket.register_b_transport(this, &LocalMemory::b_transport);
}

void LocalMemory::b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time& delay) {
  const uint64_t addr = t.get_address();
  const size_t len = t.get_data_length();
  t.set_response_status(tlm::TLM_OK_RESPONSE);
  // A write arrives over the transfer's last hop, from now until `delay` later: in PE cycles.
  const uint64_t period = ctx_.period.value(), now = sc_core::sc_time_stamp().value();
  const uint64_t from = (now + period - 1) / period,
                 to = (now + delay.value() + period - 1) / period;
  // Several frames: what comes once the first frame's rays are in goes into the next frame's
  // copy, a bank of its own with its own port (memory/memory_layout.h), so it neither waits for
  // nor delays the PE's accesses to the frame it renders; its bytes are counted.
  const bool next_copy = ctx_.frame_rays && rays.size() >= ctx_.frame_rays;
  auto host_write = [&](uint64_t address, uint64_t bytes) {
    if (next_copy)
      ctx_.memory->count(ctx_.memory->host(), bytes);
    else
      ctx_.memory->host_write(address, bytes, from, to);
  };
  if (t.is_write() && addr == kSceneBase) {
    SceneImageExtension* ext = nullptr;
    t.get_extension(ext);
    if (!ext || !ext->image) return t.set_response_status(tlm::TLM_GENERIC_ERROR_RESPONSE);
    ctx_.image = ext->image;
    host_write(0, ext->image->bytes);
  } else if (t.is_write() && addr == kRayBase && len % sizeof(Ray) == 0) {
    const size_t n = len / sizeof(Ray);
    const size_t old = rays.size();
    rays.resize(old + n);
    if (n > 0) std::memcpy(static_cast<void*>(rays.data() + old), t.get_data_ptr(), len);
    // A dynamic partition's frame buffer has a slot for every ray come.
    if (frame.size() < rays.size()) {
      frame.resize(rays.size());
      ids.resize(rays.size(), -1);
    }
    ++transfers_in;
    // A later frame's rays matter to the PE only once it has ended the frames before: it takes
    // them then, and is woken for them only if it waits for them already (a PE on the engine,
    // running ahead within a frame, learns of them at its end too).
    if (!next_copy || frames_ended_ >= old / ctx_.frame_rays)
      rays_arrived.notify(sc_core::SC_ZERO_TIME);
    const bool camera = ctx_.config.ray_generation == MachineConfig::RayGeneration::Pe;
    const MemoryAddresses& at = ctx_.memory->addresses();
    if (n > 0)
      host_write(camera ? at.rays : at.primary_ray(ctx_.place_in_frame(old)),
                 ray_transfer_bytes(ctx_.config, n, old == 0));
  } else if (t.is_write() && addr == kNoTileBase) {
    rays_expected = rays.size();
    ++transfers_in;
    rays_arrived.notify(sc_core::SC_ZERO_TIME);
    host_write(ctx_.memory->addresses().rays, kTileDescriptorBytes);
  } else if (t.is_read() && addr == kFrameBase && len == frame.size() * sizeof(PixelSum)) {
    if (len > 0)
      std::memcpy(t.get_data_ptr(), frame.data(), len);  // a PE without pixels has no frame buffer
    // The ids travel in the frame entries' bytes: one read of the frame buffer.
    if (len > 0) ctx_.memory->count(ctx_.memory->host(), frame.size() * kPixelRecordBytes);
  } else if (t.is_read() && addr == kIdBase && len == ids.size() * sizeof(int32_t)) {
    if (len > 0) std::memcpy(t.get_data_ptr(), ids.data(), len);
  } else {
    t.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
  }
}

}  // namespace rtm
