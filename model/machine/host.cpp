#include "machine/host.h"

#include <algorithm>

#include "machine/sim_time.h"
#include "memory/records.h"
#include "render/camera.h"

namespace rtm {

using sc_core::sc_time;

namespace {

uint64_t now() { return sc_core::sc_time_stamp().value(); }

/// The interconnect's answer; a transfer that would end past the horizon is the frame's time
/// error, as every long delay of the machine is (sim_time.h).
template <class Ask>
auto timed(Ask&& ask) -> decltype(ask()) {
  try {
    return ask();
  } catch (const InterconnectTimeError& e) {
    const std::string msg =
        std::string(e.what()) +
        ": past the simulated time a frame may take (SystemC counts time in 64-bit picoseconds)";
    SC_REPORT_ERROR("rtm/time", msg.c_str());
    throw;
  }
}

}  // namespace

Host::Host(sc_core::sc_module_name name, const MachineConfig& c, const Scene& s, const Grid& g,
           std::shared_ptr<const SceneImage> image, std::vector<std::vector<uint32_t>> parts,
           std::vector<Pe*> pes, Timekeeper* keeper)
    : sc_module(name),
      image(s.camera.width, s.camera.height),
      config_(c),
      scene_(s),
      grid_(g),
      image_(std::move(image)),
      parts_(std::move(parts)),
      pes_(std::move(pes)),
      scene_ready_(pes_.size(), 0),
      sleep_(keeper, 0),
      net_(c, kTimeHorizonTicks),
      deal_sleep_(keeper, 0),
      frame_sleep_(keeper, 0) {
  for (size_t i = 0; i < pes_.size(); ++i)
    links.push_back(std::make_unique<tlm_utils::simple_initiator_socket<Host>>(
        ("link" + std::to_string(i)).c_str()));
  SC_THREAD(run);
  if (c.partition == Partition::Dynamic) {
    tiles_ = screen_tiles(s.camera.width, s.camera.height, c.tile);
    dealer_ = TileDealer(tiles_.size());
    net_.keep_busy();
    SC_THREAD(deal_tiles);
  }
  if (c.frames > 1) {
    net_.keep_busy();
    times.frame_done.assign(size_t(c.frames), 0);
  }
}

void Host::transport(int pe, tlm::tlm_command cmd, uint64_t addr, unsigned char* data, size_t len,
                     sc_time delay, SceneImageExtension* ext) {
  tlm::tlm_generic_payload t;
  t.set_command(cmd);
  t.set_address(addr);
  t.set_data_ptr(data);
  t.set_data_length(unsigned(len));
  t.set_streaming_width(unsigned(len));
  t.set_byte_enable_ptr(nullptr);
  t.set_dmi_allowed(false);
  t.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  if (ext) t.set_extension(ext);
  (*links[size_t(pe)])->b_transport(t, delay);
  if (ext) t.clear_extension(ext);
  if (t.is_response_error())
    SC_REPORT_FATAL(
        "rtm/host",
        ("transfer to PE " + std::to_string(pe) + " failed: " + t.get_response_string()).c_str());
}

void Host::deliver_at(uint64_t arrive, std::function<void()> deliver) {
  if (arrive <= now())
    deliver();
  else
    pending_.emplace(arrive, std::move(deliver));  // after any due at the same time
}

void Host::host_sleep_until(uint64_t t) {
  busy_until = std::max(busy_until, sc_time::from_value(std::max(t, net_.idle_at())));
  while (!pending_.empty() && pending_.begin()->first <= t) {
    const auto first = pending_.begin();
    if (first->first > now()) sleep_(sc_time::from_value(first->first - now()));
    const std::function<void()> deliver = std::move(first->second);
    pending_.erase(first);
    deliver();
  }
  if (t > now()) sleep_(sc_time::from_value(t - now()));
}

void Host::wait_for_a_port() { host_sleep_until(net_.host_free()); }

void Host::host_work(sc_time t) {
  times.work += t.value();
  host_sleep_until(now() + t.value());
}

sc_time Host::host_cycle() const { return sc_time(config_.host_clock_ns, sc_core::SC_NS); }

void Host::run() {
  for (size_t k = 0; k < size_t(config_.frames); ++k) {
    // Frame k's scene and rays take the places frame k-2's had in every PE's local memory.
    if (k >= 2) wait_for_frame(k - 2);
    if (config_.scene_block > 0)
      stream_scene();
    else
      preprocess();
    distribute();
  }
  host_sleep_until(net_.idle_at());  // every transfer over
  times.transfer = now();
  // Rays held back until their PE has built its voxel data (voxelisation = pe).
  if (!pending_.empty()) host_sleep_until(pending_.rbegin()->first);
  if (config_.frames > 1)
    gather_frames();
  else
    gather_all();
  host_sleep_until(net_.idle_at());
  times.gathered = now();
  for (const LinkUse& l : net_.links()) times.link_busy += l.busy_ticks;
  done = true;
  sc_core::sc_stop();  // in clocked timing the clock would run on forever
}

void Host::frame_work(uint64_t items) {
  if (config_.pe_frame == PeFrame::Grid)
    host_work(checked_periods(host_cycle(), double(uint64_t(config_.host_frame_cycles) * items),
                              "the host's change of frame"));
}

void Host::voxel_work() {
  host_work(checked_periods(host_cycle(),
                            double(uint64_t(config_.host_voxel_cycles) * grid_.items.size()),
                            "the host's voxel-data generation"));
}

uint64_t pe_voxelisation_ticks(const MachineConfig& c, const Grid& g) {
  return checked_periods(sc_time(c.clock_ns, sc_core::SC_NS),
                         double(pe_voxelisation_cycles(uint64_t(c.pe_voxel_cycles),
                                                       uint64_t(c.memory_bytes_per_cycle),
                                                       g.start.size() - 1, g.items.size())),
                         "a PE's voxel-data generation")
      .value();
}

uint64_t Host::pe_ticks(uint64_t cycles, const char* what) const {
  return checked_periods(sc_time(config_.clock_ns, sc_core::SC_NS), double(cycles), what).value();
}

void Host::preprocess() {
  // Pre-processing 0: every primitive, light and the camera into the grid's frame, in fp64 (the
  // simulator framed them before simulation, as it built the grid).
  frame_work(scene_.primitives.size() + scene_.lights.size() + 1);
  // Pre-processing 1: voxel-data generation (the grid itself was built before simulation; the
  // host is charged per primitive reference it registers), unless each PE builds its own.
  if (config_.voxelisation == MachineConfig::Voxelisation::Host)
    voxel_work();
  else
    times.pe_voxelisation = pe_voxelisation_ticks(config_, grid_);
  times.voxels = now();
}

std::vector<TransferTimes> Host::send_scene_block(uint64_t bytes) {
  if (config_.broadcast) return timed([&] { return net_.broadcast(bytes, now()); });
  std::vector<TransferTimes> t;
  for (int pe = 0; pe < int(pes_.size()); ++pe)
    t.push_back(timed([&] { return net_.send(pe, bytes, now()); }));
  return t;
}

void Host::stream_scene() {
  const size_t n = scene_.primitives.size(), block = size_t(config_.scene_block);
  const bool pe_voxels = config_.voxelisation == MachineConfig::Voxelisation::Pe;
  std::vector<uint64_t> references(n, 0);
  if (pe_voxels)
    for (uint32_t prim : grid_.items) ++references[prim];
  // Per PE: when it has registered the references of every block in so far.
  std::vector<uint64_t> registered(pes_.size(), 0);
  std::vector<TransferTimes> last;
  // The lights and the camera are framed first: the lights travel with the first block. The host
  // issues each block and frames the next while the link carries it (the interconnect queues the
  // transfers in turn).
  frame_work(scene_.lights.size() + 1);
  for (size_t first = 0; first == 0 || first < n; first += block) {
    const size_t end = std::min(n, first + block);
    frame_work(end - first);
    uint64_t bytes = first == 0 ? image_->light_bytes : 0, refs = 0;
    for (size_t i = first; i < end; ++i) {
      bytes += image_->primitive_record_bytes[i];
      refs += references[i];
    }
    last = send_scene_block(bytes);
    const uint64_t work =
        pe_ticks(uint64_t(config_.pe_voxel_cycles) * refs, "a PE's voxel-data generation");
    for (size_t pe = 0; pe < pes_.size(); ++pe)
      registered[pe] = std::max(registered[pe], last[pe].end) + work;
  }
  if (!pe_voxels) {
    voxel_work();
    last = send_scene_block(image_->voxel_bytes);
  }
  times.voxels = now();
  // Voxelising, a PE writes the voxel offsets once its last block's references are in: its copy
  // is ready for rays then. What the build adds after the scene is in is on the frame's path.
  const uint64_t offsets =
      pe_ticks(pe_voxelisation_cycles(0, uint64_t(config_.memory_bytes_per_cycle),
                                      grid_.start.size() - 1, 0),
               "a PE's voxel-offset writes");
  for (size_t pe = 0; pe < pes_.size(); ++pe) {
    const TransferTimes& t = last[pe];
    scene_ready_[pe] = pe_voxels ? registered[pe] + offsets : t.arrive;
    if (pe_voxels)
      times.pe_voxelisation = std::max(times.pe_voxelisation, scene_ready_[pe] - t.end);
    write_scene(int(pe), t);
  }
}

std::vector<Ray> Host::rays_of(int pe, size_t from, size_t count) const {
  const PrimaryRays camera(scene_.camera);
  std::vector<Ray> rays;
  const auto& px = parts_[size_t(pe)];
  for (size_t i = from; i < from + count && i < px.size(); ++i)
    rays.push_back(camera.at(int(px[i] % uint32_t(scene_.camera.width)),
                             int(px[i] / uint32_t(scene_.camera.width))));
  return rays;
}

// Each transfer is asked of the interconnect when the host issues it; its data lands in the PE's
// memory when the interconnect says it arrives, and the host goes on once it has a free port (on
// one medium: once the transfer is over, as the original link had it).

std::pair<uint64_t, std::function<void()>> Host::ray_write(int pe, std::vector<Ray> rays,
                                                           uint64_t ready, bool first) {
  // With ray generation on the PEs only the camera and the PE's share of the screen (or tile)
  // travel; the simulator still hands over the rays the PE will generate.
  const uint64_t bytes = ray_transfer_bytes(config_, rays.size(), first);
  const TransferTimes t = timed([&] { return net_.send(pe, bytes, ready); });
  auto data = std::make_shared<std::vector<Ray>>(std::move(rays));
  // Not before the PE has its scene (and, voxelising, its voxel data): then what is left of it.
  const uint64_t at = std::max(t.arrive, scene_ready_[size_t(pe)]);
  return {at, [this, pe, data, d = t.end - std::min(t.end, at)] {
            transport(pe, tlm::TLM_WRITE_COMMAND, LocalMemory::kRayBase,
                      reinterpret_cast<unsigned char*>(data->data()), data->size() * sizeof(Ray),
                      sc_time::from_value(d));
          }};
}

void Host::send_rays(int pe, std::vector<Ray> rays) {
  if (rays.empty()) return;
  auto [at, write] = ray_write(pe, std::move(rays), now(), true);
  deliver_at(at, std::move(write));
  wait_for_a_port();
}

std::pair<uint64_t, std::function<void()>> Host::send_tile(int pe, std::optional<size_t> k,
                                                           uint64_t ready, bool first) {
  if (k) {
    // The PE's frame-buffer slots go on from those it has: the host maps them back by parts_.
    std::vector<uint32_t>& px = parts_[size_t(pe)];
    const size_t from = px.size();
    const std::vector<uint32_t> tile = tile_pixels(tiles_[*k], scene_.camera.width);
    px.insert(px.end(), tile.begin(), tile.end());
    return ray_write(pe, rays_of(pe, from, tile.size()), ready, first);
  }
  const TransferTimes t = timed([&] { return net_.send(pe, kTileDescriptorBytes, ready); });
  const uint64_t at = std::max(t.arrive, scene_ready_[size_t(pe)]);
  return {at, [this, pe, d = t.end - std::min(t.end, at)] {
            unsigned char none[kTileDescriptorBytes] = {};  // height 0
            transport(pe, tlm::TLM_WRITE_COMMAND, LocalMemory::kNoTileBase, none, sizeof none,
                      sc_time::from_value(d));
          }};
}

void Host::ask_for_tile(int pe) {
  asked_.push_back({now(), pe});
  // Taken once every request made now is in: one tick later.
  deal_sleep_.want(now() + 1);
  if (config_.arbitration == MachineConfig::Arbitration::Kernel)
    asked_event_.notify(sc_time::from_value(1));
}

void Host::deal_tiles() {
  sc_core::sc_event_or_list either = deal_sleep_.event() | asked_event_;
  for (;;) {
    deal_sleep_.wait(&either);
    const uint64_t t = now();
    // The answers due land first, ...
    while (!answers_.empty() && answers_.begin()->first <= t) {
      const std::function<void()> write = std::move(answers_.begin()->second);
      answers_.erase(answers_.begin());
      write();
    }
    // ... then the requests made before now go on the link, ...
    std::sort(asked_.begin(), asked_.end());
    size_t made = 0;
    for (; made < asked_.size() && asked_[made].at < t; ++made) {
      const Ask& a = asked_[made];
      const TransferTimes on = timed([&] { return net_.gather(a.pe, kTileRequestBytes, a.at); });
      arrived_.push_back({on.end, a.pe});  // the host acts on a whole request
      // Answered one tick after it arrives, when every request arriving then is in (now, below,
      // if that has passed).
      if (on.end + 1 > t) deal_sleep_.want(on.end + 1);
    }
    asked_.erase(asked_.begin(), asked_.begin() + std::ptrdiff_t(made));
    // ... and those arrived before now are answered, in arrival order.
    std::sort(arrived_.begin(), arrived_.end());
    size_t answered = 0;
    for (; answered < arrived_.size() && arrived_[answered].at < t; ++answered) {
      const Ask& a = arrived_[answered];
      auto [at, write] = send_tile(a.pe, dealer_.request(a.pe), a.at, false);
      if (at <= t)
        write();
      else {
        answers_.emplace(at, std::move(write));
        deal_sleep_.want(at);
      }
    }
    arrived_.erase(arrived_.begin(), arrived_.begin() + std::ptrdiff_t(answered));
  }
}

std::vector<uint32_t> Host::tiles_per_pe() const {
  std::vector<uint32_t> n(pes_.size(), 0);
  for (int pe : dealer_.owners())
    if (pe >= 0) ++n[size_t(pe)];
  return n;
}

uint64_t Host::scene_link_bytes() const {
  return image_->bytes -
         (config_.voxelisation == MachineConfig::Voxelisation::Pe ? image_->voxel_bytes : 0);
}

void Host::deliver_scene(int pe, const TransferTimes& t) {
  // Voxelising, the PE builds its voxel data once the scene is in: its copy is whole, and ready
  // for its rays, that long after. The voxel data's bytes are written into its memory with the
  // scene's, as when they crossed the link.
  scene_ready_[size_t(pe)] = config_.voxelisation == MachineConfig::Voxelisation::Pe
                                 ? t.end + times.pe_voxelisation
                                 : t.arrive;
  write_scene(pe, t);
}

void Host::write_scene(int pe, const TransferTimes& t) {
  deliver_at(t.arrive, [this, pe, d = t.end - t.arrive] {
    SceneImageExtension ext;
    ext.image = image_;
    unsigned char unused = 0;  // the image travels in the extension; its size times the transfer
    transport(pe, tlm::TLM_WRITE_COMMAND, LocalMemory::kSceneBase, &unused, 1,
              sc_time::from_value(d), &ext);
  });
}

void Host::send_scene(int pe) {
  deliver_scene(pe, timed([&] { return net_.send(pe, scene_link_bytes(), now()); }));
  wait_for_a_port();
}

void Host::send_scene_to_all() {
  const int n = int(pes_.size());
  if (!config_.broadcast) {
    for (int pe = 0; pe < n; ++pe) send_scene(pe);
    return;
  }
  const std::vector<TransferTimes> t =
      timed([&] { return net_.broadcast(scene_link_bytes(), now()); });
  for (int pe = 0; pe < n; ++pe) deliver_scene(pe, t[size_t(pe)]);
  wait_for_a_port();
}

void Host::distribute() {
  const int n = int(pes_.size());
  const bool pe_rays = config_.ray_generation == MachineConfig::RayGeneration::Pe;
  const size_t pixels = size_t(scene_.camera.width) * size_t(scene_.camera.height);
  const bool scene_sent = config_.scene_block > 0;  // stream_scene sent it
  // A dynamic partition's first tiles, one to each PE in turn while any are left, before any PE
  // can ask for more.
  std::vector<std::optional<size_t>> first_tile(static_cast<size_t>(n));
  if (config_.partition == Partition::Dynamic)
    for (int pe = 0; pe < n; ++pe) first_tile[size_t(pe)] = dealer_.request(pe);
  if (config_.ray_block == 0 || pe_rays) {
    // The paper's flow: all pre-processing first, then every PE's data in turn.
    if (!pe_rays)
      host_work(checked_periods(host_cycle(), double(uint64_t(config_.host_ray_cycles) * pixels),
                                "the host's primary-ray generation"));
    times.rays = now();
    if (config_.broadcast && !scene_sent) send_scene_to_all();
    for (int pe = 0; pe < n; ++pe) {
      if (!config_.broadcast && !scene_sent) send_scene(pe);
      if (config_.partition != Partition::Dynamic) {
        send_rays(pe, rays_of(pe, 0, parts_[size_t(pe)].size()));
        continue;
      }
      // A dynamic partition's first tile, unasked, so that no PE starts idle.
      auto [at, write] = send_tile(pe, first_tile[size_t(pe)], now(), true);
      deliver_at(at, std::move(write));
      wait_for_a_port();
    }
    return;
  }
  // Streaming: the scene first, then primary rays block by block, generation overlapping the PEs'
  // work.
  if (!scene_sent) send_scene_to_all();
  for (size_t from = 0;; from += size_t(config_.ray_block)) {
    bool any = false;
    for (int pe = 0; pe < n; ++pe) {
      std::vector<Ray> rays = rays_of(pe, from, size_t(config_.ray_block));
      if (rays.empty()) continue;
      any = true;
      host_work(checked_periods(host_cycle(),
                                double(uint64_t(config_.host_ray_cycles) * rays.size()),
                                "the host's primary-ray generation"));
      send_rays(pe, std::move(rays));
    }
    if (!any) break;
  }
  times.rays = now();
}

void Host::read_frame(int pe, sc_time delay) {
  // Every frame's slots (frames > 1: frame after frame, each the same pixels).
  const auto& px = parts_[size_t(pe)];
  const size_t slots = px.size() * size_t(config_.frames);
  std::vector<PixelSum> frame(slots);
  std::vector<int32_t> ids(slots);
  transport(pe, tlm::TLM_READ_COMMAND, LocalMemory::kFrameBase,
            reinterpret_cast<unsigned char*>(frame.data()), frame.size() * sizeof(PixelSum), delay);
  transport(pe, tlm::TLM_READ_COMMAND, LocalMemory::kIdBase,
            reinterpret_cast<unsigned char*>(ids.data()), ids.size() * sizeof(int32_t),
            sc_core::SC_ZERO_TIME);
  for (size_t i = 0; i < slots; ++i) {
    image.rgb[px[i % px.size()]] = frame[i].value();
    image.ids[px[i % px.size()]] = ids[i];
  }
}

void Host::gather(int pe) {
  const TransferTimes t =
      timed([&] { return net_.gather(pe, parts_[size_t(pe)].size() * kPixelRecordBytes, now()); });
  // The PE is done, so its frame buffer no longer changes: read at once, the interconnect timing
  // the transfer. The ids travel in the same 16 bytes a pixel.
  read_frame(pe, sc_time::from_value(t.end - t.arrive));
  wait_for_a_port();
}

void Host::gather_streamed() {
  for (Pe* pe : pes_)
    if (!pe->finished()) sc_core::wait(pe->finished_event);
  for (Pe* pe : pes_) times.pes_done = std::max(times.pes_done, pe->ctx.counters.finish);
  // Each PE's frame buffer in blocks of gather_block slots, each ready once its last pixel is
  // done and the host has issued its last transfer to the PEs. The host takes them first come,
  // first served (of equal times, by PE, then block): asked for in that order, each no earlier
  // than it is ready, the interconnect gives the times an online host would get, nothing else
  // asking for a link meanwhile. The frame buffers no longer change, so they are read at the end.
  struct Block {
    uint64_t ready;
    int pe;
    size_t pixels;
  };
  std::vector<Block> blocks;
  const size_t per_block = size_t(config_.gather_block);
  const bool dynamic = config_.partition == Partition::Dynamic;
  for (int pe = 0; pe < int(pes_.size()); ++pe) {
    const size_t n = parts_[size_t(pe)].size();
    const std::vector<uint64_t>& done = pes_[size_t(pe)]->ctx.pixel_done;
    if (done.size() != n)
      throw std::logic_error("PE " + std::to_string(pe) + " finished " +
                             std::to_string(done.size()) + " pixels of " + std::to_string(n));
    for (size_t first = 0; first < n; first += per_block) {
      const size_t last = std::min(n, first + per_block);
      const uint64_t ready = *std::max_element(done.begin() + std::ptrdiff_t(first),
                                               done.begin() + std::ptrdiff_t(last));
      blocks.push_back({dynamic ? ready : std::max(ready, times.transfer), pe, last - first});
    }
  }
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const Block& a, const Block& b) { return a.ready < b.ready; });
  // A dynamic partition's tile records were on the links all along, asked for as they happened:
  // the blocks go between them.
  for (const Block& b : blocks)
    timed([&] {
      const uint64_t bytes = gather_block_bytes(b.pixels);
      return dynamic ? net_.gather_in_gaps(b.pe, bytes, b.ready)
                     : net_.gather(b.pe, bytes, b.ready);
    });
  for (int pe = 0; pe < int(pes_.size()); ++pe) read_frame(pe, sc_core::SC_ZERO_TIME);
}

void Host::gather_all() {
  const int n = int(pes_.size());
  if (config_.gather == MachineConfig::Gather::Streamed) return gather_streamed();
  if (config_.gather == MachineConfig::Gather::AfterAll) {
    for (Pe* pe : pes_)
      if (!pe->finished()) sc_core::wait(pe->finished_event);
    times.pes_done = now();
    for (int pe = 0; pe < n; ++pe) gather(pe);
    return;
  }
  // Whichever PEs are done, in PE order; then wait for the next to finish. A gather waits for its
  // links and a host port, so PEs finishing meanwhile queue up.
  std::vector<bool> gathered(size_t(n), false);
  for (int left = n; left > 0;) {
    int ready = -1;
    sc_core::sc_event_or_list pending;
    for (int pe = 0; pe < n && ready < 0; ++pe) {
      if (gathered[size_t(pe)]) continue;
      if (pes_[size_t(pe)]->finished())
        ready = pe;
      else
        pending |= pes_[size_t(pe)]->finished_event;
    }
    if (ready < 0) {
      sc_core::wait(pending);
      continue;
    }
    gather(ready);  // takes time: look again from the first PE afterwards
    gathered[size_t(ready)] = true;
    --left;
  }
  // The frame's PE phase ends with the last PE, whatever the link was doing then.
  for (Pe* pe : pes_) times.pes_done = std::max(times.pes_done, pe->ctx.counters.finish);
}

size_t Host::frames_ended_by_all() const {
  size_t least = SIZE_MAX;  // a PE without pixels has no frames to end
  for (size_t pe = 0; pe < pes_.size(); ++pe)
    if (!parts_[pe].empty()) least = std::min(least, pes_[pe]->memory.frames_ended());
  return least;
}

void Host::pe_frame_ended(int pe) {
  const size_t k = pes_[size_t(pe)]->memory.frames_ended() - 1;
  frame_ended_event_.notify(sc_core::SC_ZERO_TIME);
  // The PE switching to the next frame (building its voxel data) is no stall.
  busy_until =
      std::max(busy_until, sc_time::from_value(now() + pes_[size_t(pe)]->ctx.frame_switch));
  // Its pixels go on the links now, before anything the host sends later: frame k+2, which takes
  // the places frame k had, comes only once every PE has ended frame k (run), so on every PE's
  // link it follows that frame's pixels out of its frame buffer.
  if (config_.gather != MachineConfig::Gather::AfterAll) return gather_frame(pe, k, now());
  if (frames_ended_by_all() <= k) return;
  for (int p = 0; p < int(pes_.size()); ++p) gather_frame(p, k, now());
}

void Host::wait_for_frame(size_t k) {
  const sc_core::sc_event_or_list either = frame_sleep_.event() | frame_ended_event_;
  while (frames_ended_by_all() <= k) {
    host_sleep_until(now());  // the writes due
    if (!pending_.empty()) {
      frame_sleep_.want(pending_.begin()->first);
      // PEs waiting for these writes are no stall.
      busy_until = std::max(busy_until, sc_time::from_value(pending_.rbegin()->first));
    }
    frame_sleep_.wait(&either);
  }
}

void Host::gather_frame(int pe, size_t k, uint64_t ready) {
  const size_t n = parts_[size_t(pe)].size();
  if (n == 0) return;
  // Blocks of gather_block slots each once its pixels are done, or the frame's part at once.
  const bool streamed = config_.gather == MachineConfig::Gather::Streamed;
  const size_t per_block = streamed ? size_t(config_.gather_block) : n;
  const auto done = pes_[size_t(pe)]->ctx.pixel_done.begin() + std::ptrdiff_t(k * n);
  for (size_t first = 0; first < n; first += per_block) {
    const size_t last = std::min(n, first + per_block);
    const uint64_t at =
        streamed ? *std::max_element(done + std::ptrdiff_t(first), done + std::ptrdiff_t(last))
                 : ready;
    const uint64_t bytes =
        streamed ? gather_block_bytes(last - first) : (last - first) * kPixelRecordBytes;
    const TransferTimes t = timed([&] { return net_.gather_in_gaps(pe, bytes, at); });
    times.frame_done[k] = std::max(times.frame_done[k], t.end);
  }
}

void Host::gather_frames() {
  for (Pe* pe : pes_)
    if (!pe->finished()) sc_core::wait(pe->finished_event);
  for (Pe* pe : pes_) times.pes_done = std::max(times.pes_done, pe->ctx.counters.finish);
  // The last frame, which no PE told the end of: as the gather asks, in the order the PEs ended
  // it (of equal times, by PE).
  const size_t last = size_t(config_.frames) - 1;
  std::vector<std::pair<uint64_t, int>> ends;
  for (int pe = 0; pe < int(pes_.size()); ++pe)
    if (!parts_[size_t(pe)].empty()) ends.push_back({pes_[size_t(pe)]->ctx.counters.finish, pe});
  std::sort(ends.begin(), ends.end());
  const uint64_t all_done = ends.empty() ? now() : ends.back().first;
  for (auto [end, pe] : ends)
    gather_frame(pe, last, config_.gather == MachineConfig::Gather::AfterAll ? all_done : end);
  for (int pe = 0; pe < int(pes_.size()); ++pe) read_frame(pe, sc_core::SC_ZERO_TIME);
}

}  // namespace rtm
