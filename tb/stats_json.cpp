#include "stats_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "build_info.h"
#include "fnv1a.h"

namespace rtm {

namespace {

// Each group of figures is spelled once: the nested objects and the flat summary use these.

nlohmann::json rays_json(const TraceCounts& c) {
  nlohmann::json rays;
  for (int k = 0; k < kRayKinds; ++k) rays[ray_kind_name(RayKind(k))] = c.rays[size_t(k)];
  return rays;
}

nlohmann::json counts_json(const TraceCounts& c) {
  return {{"rays", rays_json(c)},
          {"voxel_steps", c.voxel_steps},
          {"intersection_tests", c.intersection_tests},
          {"clip_tests", c.clip_tests}};
}

nlohmann::json utilisation_json(const UnitShares& u) {
  nlohmann::json j = nlohmann::json::object();
  for (const UnitSpec& s : unit_table())
    if (s.in_utilisation) j[s.name] = u[s.kind];
  return j;
}

nlohmann::json pe_utilisation_json(const FrameProfile& f) {
  nlohmann::json j = utilisation_json(f.busy);
  j["credit_stall"] = f.credit_stall;
  return j;
}

/// One PE's figure `of` per unit (replicated units: summed).
nlohmann::json unit_figures(const PeCounters& p, uint64_t UnitStats::*of) {
  nlohmann::json j = nlohmann::json::object();
  for (const UnitSpec& s : unit_table())
    if (s.in_utilisation) j[s.name] = p.total(s.kind).*of;
  return j;
}

nlohmann::json phases_json(const FrameProfile& f) {
  return {{"host_preprocess_cycles", f.host_preprocess},
          {"transfer_cycles", f.transfer},
          {"pe_cycles", f.pe},
          {"gather_cycles", f.gather}};
}

nlohmann::json error_json(const ImageError& e) {
  return {{"rmse", e.rmse},
          {"psnr_db", std::isfinite(e.psnr_db) ? nlohmann::json(e.psnr_db) : nlohmann::json("inf")},
          {"max_abs", e.max_abs},
          {"pixels_over_1_255", e.pixels_over_1_255},
          {"primary_ids_differing", e.primary_ids_differing}};
}

/// Why the differing pixels differ (error/error_causes.h): pixels per cause (every cause, so a
/// script can rely on the keys), per shape of the parting ray's primitive, and per generation,
/// kind and cause of the ray where the machine's tree first parts from the reference's.
nlohmann::json causes_json(const ErrorCauses& e) {
  nlohmann::json by_cause = nlohmann::json::object(), by_shape = nlohmann::json::object(),
                 partings = nlohmann::json::array();
  for (int k = 1; k < kErrorCauses; ++k)
    by_cause[error_cause_name(ErrorCause(k))] = e.by_cause[size_t(k)];
  for (int k = 0; k < kShapeKinds; ++k)
    if (e.by_shape[size_t(k)]) by_shape[shape_name(ShapeKind(k))] = e.by_shape[size_t(k)];
  for (const CauseCount& c : e.counts)
    partings.push_back({{"generation", c.generation},
                        {"kind", ray_kind_name(c.kind)},
                        {"cause", error_cause_name(c.cause)},
                        {"pixels", c.pixels}});
  return {{"pixels", e.differing},
          {"by_cause", by_cause},
          {"by_shape", by_shape},
          {"partings", partings}};
}

/// A configuration value as its key's type: an integer or a number, a flag as a boolean, a choice
/// as its name. From the key's own text (ConfigKey::get), which reads back as the same value.
nlohmann::json config_value(const ConfigKey& k, const MachineConfig& c) {
  const std::string v = k.get(c);
  switch (k.type) {
    case ConfigKey::Type::Integer:
      return std::stoll(v);
    case ConfigKey::Type::Number:
      return std::stod(v);
    case ConfigKey::Type::Flag:
      return v == "true";
    case ConfigKey::Type::Choice:
    case ConfigKey::Type::Text:
      break;
  }
  return v;
}

/// A simulated time, in ticks, in whole PE cycles.
uint64_t whole_cycles(uint64_t ticks, const MachineConfig& c) {
  return uint64_t(std::llround(sc_core::sc_time::from_value(ticks) /
                               sc_core::sc_time(c.clock_ns, sc_core::SC_NS)));
}

double sim_time_ns(const MachineResult& m) {
  return sc_core::sc_time::from_value(m.end).to_seconds() * 1e9;
}

/// The topology, each link's busy time and bytes, and their totals.
nlohmann::json interconnect_json(const MachineResult& m, const MachineConfig& c) {
  nlohmann::json links = nlohmann::json::array();
  uint64_t bytes = 0;
  for (const LinkUse& l : m.links) {
    const sc_core::sc_time busy = sc_core::sc_time::from_value(l.busy_ticks);
    links.push_back({{"name", l.name},
                     {"busy_cycles", whole_cycles(l.busy_ticks, c)},
                     {"busy_seconds", busy.to_seconds()},
                     {"bytes", l.bytes},
                     {"transfers", l.hops}});
    bytes += l.bytes;
  }
  return {{"topology", to_string(c.link_topology)},
          {"links", links},
          {"busy_cycles", whole_cycles(m.host.link_busy, c)},
          {"busy_seconds", sc_core::sc_time::from_value(m.host.link_busy).to_seconds()},
          {"bytes", bytes}};
}

namespace {

double rate(uint64_t hits, uint64_t misses) {
  return hits + misses == 0 ? 1.0 : double(hits) / double(hits + misses);
}

/// The local memory of the PE that needs the most (all PEs hold the same scene copy), and what
/// every PE's memory did, summed (docs/memory.md).
nlohmann::json memory_json(const MachineResult& r, const MachineConfig& c) {
  const size_t fullest = fullest_pe(r.memory);
  const MemoryLayout& m = r.memory[fullest];
  nlohmann::json sections = nlohmann::json::object();
  for (const MemorySection& s : m.sections) sections[s.name] = s.bytes;
  nlohmann::json requesters = nlohmann::json::object();
  std::vector<uint64_t> ports;
  MemoryUse sum;
  for (const MemoryUse& u : r.memory_use) {
    for (const MemoryUse::Requester& q : u.requesters) {
      nlohmann::json& j = requesters[q.name];
      for (auto [key, v] : {std::pair<const char*, uint64_t>{"requests", q.requests},
                            {"bytes", q.bytes},
                            {"stall_cycles", q.stall_cycles},
                            {"wait_cycles", q.wait_cycles},
                            {"access_cycles", q.access_cycles}})
        j[key] = (j.contains(key) ? j[key].get<uint64_t>() : 0) + v;
    }
    if (ports.size() < u.port_busy_cycles.size()) ports.resize(u.port_busy_cycles.size());
    for (size_t i = 0; i < u.port_busy_cycles.size(); ++i) ports[i] += u.port_busy_cycles[i];
    sum.beats += u.beats;
    sum.bank_conflicts += u.bank_conflicts;
    sum.coef_hits += u.coef_hits;
    sum.coef_misses += u.coef_misses;
    sum.coef_evictions += u.coef_evictions;
    sum.cache_hits += u.cache_hits;
    sum.cache_misses += u.cache_misses;
    sum.cache_line_fills += u.cache_line_fills;
  }
  nlohmann::json port_json = nlohmann::json::array();
  const double pe_cycles = double(r.cycles) * double(c.pes);
  for (uint64_t busy : ports)
    port_json.push_back(
        {{"busy_cycles", busy}, {"utilisation", pe_cycles > 0 ? double(busy) / pe_cycles : 0.0}});
  uint64_t wait = 0, access = 0;
  for (const MemoryUse& u : r.memory_use) wait += u.wait_cycles(), access += u.access_cycles();
  const nlohmann::json cache =
      c.voxel_cache_bytes > 0 ? nlohmann::json{{"bytes", c.voxel_cache_bytes},
                                               {"hits", sum.cache_hits},
                                               {"misses", sum.cache_misses},
                                               {"line_fills", sum.cache_line_fills},
                                               {"hit_rate", rate(sum.cache_hits, sum.cache_misses)}}
                              : nlohmann::json(nullptr);
  return {{"capacity_bytes", m.capacity},
          {"fullest_pe", fullest},
          {"sections_bytes", sections},
          {"used_bytes", m.used},
          {"spill_area_bytes", m.spill_bytes()},
          {"spill_area_rays", m.spill_rays()},
          {"spill_record_bytes", kSpillRecordBytes},
          {"ideal", r.memory_use.empty() || r.memory_use.front().ideal},
          {"requesters", requesters},
          {"ports", port_json},
          {"beats", sum.beats},
          {"bank_conflicts", sum.bank_conflicts},
          {"wait_cycles", wait},
          {"access_cycles", access},
          {"coefficient_ram",
           {{"capacity_primitives", c.mac_ram_primitives},
            {"hits", sum.coef_hits},
            {"misses", sum.coef_misses},
            {"evictions", sum.coef_evictions},
            {"hit_rate", rate(sum.coef_hits, sum.coef_misses)}}},
          {"voxel_cache", cache}};
}

/// One PE's memory traffic.
nlohmann::json memory_access_json(const MemoryUse& u) {
  uint64_t requests = 0, bytes = 0, stall = 0;
  for (const MemoryUse::Requester& q : u.requesters)
    requests += q.requests, bytes += q.bytes, stall += q.stall_cycles;
  return {{"requests", requests},
          {"bytes", bytes},
          {"stall_cycles", stall},
          {"wait_cycles", u.wait_cycles()},
          {"port_busy_cycles", u.port_busy_cycles},
          {"bank_conflicts", u.bank_conflicts},
          {"coefficient_ram_misses", u.coef_misses}};
}

/// The tiles each PE got: least, mean and most (null for a static partition).
nlohmann::json tiles_json(const std::vector<uint32_t>& tiles) {
  if (tiles.empty()) return nullptr;
  uint64_t sum = 0;
  for (uint32_t t : tiles) sum += t;
  return {{"min", *std::min_element(tiles.begin(), tiles.end())},
          {"mean", double(sum) / double(tiles.size())},
          {"max", *std::max_element(tiles.begin(), tiles.end())}};
}

}  // namespace

/// The frames of the run: when each was whole at the host, each one's time after the one before
/// (the first's from the start), and the steady state's (MachineResult::frame_cycles).
nlohmann::json frames_json(const MachineResult& m, const MachineConfig& c) {
  const std::vector<uint64_t> done =
      m.frame_done.empty() ? std::vector<uint64_t>{m.cycles} : m.frame_done;
  nlohmann::json each = nlohmann::json::array();
  for (size_t k = 0; k < done.size(); ++k) each.push_back(done[k] - (k ? done[k - 1] : 0));
  const double seconds = double(m.frame_cycles()) * c.clock_ns * 1e-9;
  return {{"count", done.size()},
          {"done_cycles", done},
          {"frame_cycles", each},
          {"steady_frame_cycles", m.frame_cycles()},
          {"frames_per_s", seconds > 0 ? 1 / seconds : 0.0}};
}

nlohmann::json machine_json(const MachineResult& m, const MachineConfig& c) {
  auto cyc = [&](uint64_t ticks) { return whole_cycles(ticks, c); };
  const FrameStats& s = m.stats;
  nlohmann::json per_pe = nlohmann::json::array();
  for (size_t i = 0; i < m.per_pe.size(); ++i) {
    const PeCounters& p = m.per_pe[i];
    nlohmann::json search_units = nlohmann::json::array();
    for (const SearchUnitShares& u : s.search_units[i])
      search_units.push_back({{"busy", u.busy}, {"issue", u.issue}});
    per_pe.push_back({{"cycles", cyc(p.finish)},
                      {"start_cycle", cyc(p.start)},
                      {"credit_stall_cycles", cyc(p.credit_stall)},
                      {"tiles", i < m.tiles.size() ? m.tiles[i] : 0},
                      {"tile_wait_cycles", cyc(p.tile_wait)},
                      {"frame_wait_cycles", cyc(p.frame_wait)},
                      {"rays", p.counts.total_rays()},
                      {"spills", p.spills},
                      {"memory_used_bytes", m.memory[i].used},
                      {"spill_area_rays", m.memory[i].spill_rays()},
                      {"memory_access", memory_access_json(m.memory_use[i])},
                      {"busy_cycles", unit_figures(p, &UnitStats::busy_cycles)},
                      {"issue_cycles", unit_figures(p, &UnitStats::issue_cycles)},
                      {"held_cycles", unit_figures(p, &UnitStats::held_cycles)},
                      {"starved_cycles", unit_figures(p, &UnitStats::starved_cycles)},
                      {"search_units", search_units}});
  }
  nlohmann::json fifo;
  for (const FifoSummary& f : m.fifos)
    fifo[f.kind] = {{"depth", f.depth}, {"peak", f.peak}, {"mean", f.mean}};
  nlohmann::json config;
  for (const ConfigKey& k : config_keys()) config[k.name] = config_value(k, c);
  return {
      {"pes", c.pes},
      {"timing", to_string(c.timing)},
      {"precision", to_string(c.precision)},
      {"partition", to_string(c.partition)},
      {"search_units", c.search_units},
      {"pe_simulation",
       {{"engine", m.engine_unsupported.empty()},
        {"modules_because", m.engine_unsupported.empty() ? nlohmann::json(nullptr)
                                                         : nlohmann::json(m.engine_unsupported)}}},
      {"cycles", m.cycles},
      {"sim_time_ns", sim_time_ns(m)},
      {"mac",
       {{"products", m.mac_products},
        {"busy_cycles", m.mac_busy_cycles},
        {"issue_cycles", m.mac_issue_cycles}}},
      {"spills", m.spills},
      {"host",
       {{"voxels_done_cycle", cyc(m.host.voxels)},
        {"rays_done_cycle", cyc(m.host.rays)},
        {"work_cycles", cyc(m.host.work)},
        {"transfer_done_cycle", cyc(m.host.transfer)},
        {"pes_done_cycle", cyc(m.host.pes_done)},
        {"gathered_cycle", cyc(m.host.gathered)},
        {"link_busy_cycles", cyc(m.host.link_busy)},
        {"scene_bytes", m.scene_bytes},
        {"pe_voxelisation_cycles", cyc(m.host.pe_voxelisation)}}},
      {"interconnect", interconnect_json(m, c)},
      {"memory", memory_json(m, c)},
      {"utilisation", utilisation_json(s.utilisation)},
      {"pe_utilisation", pe_utilisation_json(s.profile)},
      {"pe_issue", utilisation_json(s.profile.issue)},
      {"pe_occupancy", utilisation_json(s.profile.occupancy)},
      {"pe_starved", utilisation_json(s.profile.starved)},
      {"phases", phases_json(s.profile)},
      {"load_imbalance", s.profile.imbalance},
      {"tiles_per_pe", tiles_json(m.tiles)},
      {"frames", frames_json(m, c)},
      {"mac_bound_cycles", s.mac_bound_cycles},
      {"cycles_over_mac_bound", s.cycles_over_mac_bound},
      {"bottleneck", s.bottleneck.name},
      {"bottleneck_reason", s.bottleneck.reason},
      {"left_out",
       {{"units", m.left_out_units},
        {"mac_schedule", to_string(c.mac_schedule)},
        {"mac_products_saved", m.mac_products_saved},
        {"mac_cycles_saved", m.mac_cycles_saved},
        {"scene_needs",
         {{"shadow_rays", m.needs.shadow_rays},
          {"reflected_rays", m.needs.reflected_rays},
          {"transmitted_rays", m.needs.transmitted_rays},
          {"background", m.needs.background},
          {"deepest_generation", m.needs.deepest_generation},
          {"clipped_primitives", m.needs.clipped_primitives},
          {"mac_products_per_test_full", kMacProducts},
          {"mac_products_per_test_sparse",
           m.needs.mac_ops.empty()
               ? 0.0
               : double(m.needs.products_sparse) / double(m.needs.mac_ops.size())},
          {"grid", m.needs.grid}}}}},
      {"per_pe", per_pe},
      {"fifo", fifo},
      {"preset", c.preset},
      {"config", config}};
}

constexpr double kJoulesPerPj = 1e-12;

/// What the machine costs (cost/unit_cost.h, docs/cost.md): each kind of unit's inventory, area
/// and dynamic energy, the totals, the frame's leakage, energy and average power.
nlohmann::json cost_json(const MachineCost& m) {
  nlohmann::json units = nlohmann::json::object();
  for (const UnitCost& u : m.units) {
    const UnitInventory& i = u.inventory;
    nlohmann::json elements = nlohmann::json::object();
    for (size_t o = 0; o < kOps; ++o)
      for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        const bool integer = Op(o) == Op::IntAdd || Op(o) == Op::IntCompare;
        if (integer && p == Precision::Fp64) continue;
        const uint64_t n = i.elements.of(Op(o), p);
        if (n)
          elements[integer ? std::string(op_name(Op(o)))
                           : std::string(op_name(Op(o))) + "_" + to_string(p)] = n;
      }
    nlohmann::json srams = nlohmann::json::array();
    for (const Sram& r : i.srams)
      srams.push_back({{"name", r.name}, {"bytes", r.bytes}, {"word_bits", r.word_bits}});
    units[unit_name(i.kind)] = {{"units", i.units},
                                {"elements", elements},
                                {"register_bits", i.register_bits},
                                {"fifo_bits", i.fifo_bits},
                                {"srams", srams},
                                {"logic_mm2", i.logic_um2 * 1e-6},
                                {"sram_mm2", i.sram_um2 * 1e-6},
                                {"dynamic_j", u.dynamic_pj * kJoulesPerPj}};
  }
  return {{"technology", m.technology},
          {"units", units},
          {"pe_logic_mm2", m.pe_logic_mm2},
          {"pe_sram_mm2", m.pe_sram_mm2},
          {"interconnect_mm2", m.interconnect_mm2},
          {"logic_mm2", m.logic_mm2},
          {"sram_mm2", m.sram_mm2},
          {"area_mm2", m.area_mm2()},
          {"memory_mm2", m.memory_mm2},
          {"memory_capacity_bytes", m.memory_capacity_bytes},
          {"local_memory_dynamic_j", m.memory_dynamic_pj * kJoulesPerPj},
          {"link_dynamic_j", m.link_dynamic_pj * kJoulesPerPj},
          {"voxelisation_dynamic_j", m.voxelisation_dynamic_pj * kJoulesPerPj},
          {"dynamic_j", m.dynamic_pj * kJoulesPerPj},
          {"leakage_j", m.leakage_pj * kJoulesPerPj},
          {"energy_per_frame_j", m.energy_pj * kJoulesPerPj},
          {"energy_per_ray_j", m.energy_per_ray_pj * kJoulesPerPj},
          {"energy_per_pixel_j", m.energy_per_pixel_pj * kJoulesPerPj},
          {"frame_seconds", m.frame_seconds},
          {"power_w", m.power_w}};
}

/// The sweep's figures of merit: area (on chip), the frame's energy and average power, frames per
/// second per mm², frames per joule, and energy times delay.
nlohmann::json cost_summary_json(const MachineCost& m) {
  const double e = m.energy_pj * kJoulesPerPj, a = m.area_mm2(), frame_seconds = m.frame_seconds;
  nlohmann::json j = {
      {"area_mm2", a},
      {"energy_j", e},
      {"power_w", m.power_w},
      {"frames_per_s_per_mm2", frame_seconds > 0 && a > 0 ? 1 / frame_seconds / a : 0.0},
      {"frames_per_j", e > 0 ? 1 / e : 0.0},
      {"energy_delay", e * frame_seconds}};
  // The frame's energy split: each unit's dynamic energy, the local memories', the link's, leakage.
  for (const UnitCost& u : m.units)
    j[std::string("energy_") + unit_name(u.inventory.kind) + "_j"] = u.dynamic_pj * kJoulesPerPj;
  j["energy_local_memory_j"] = m.memory_dynamic_pj * kJoulesPerPj;
  j["energy_link_j"] = m.link_dynamic_pj * kJoulesPerPj;
  j["energy_leakage_j"] = m.leakage_pj * kJoulesPerPj;
  return j;
}

/// Copies an object's fields into `to`, each name prefixed.
void flatten_into(nlohmann::json& to, const std::string& prefix, const nlohmann::json& from) {
  for (const auto& [key, value] : from.items()) to[prefix + key] = value;
}

/// One flat object of the run's headline figures: exactly the metric columns of a sweep's
/// results.csv (scripts/rtmsweep reads its metrics from it alone).
nlohmann::json summary_json(const MachineResult& m, const MachineConfig& c, const MachineCost& cost,
                            const ImageError& err) {
  const FrameStats& s = m.stats;
  nlohmann::json j = {{"cycles", m.cycles},
                      {"frame_cycles", m.frame_cycles()},
                      {"wall_seconds", m.wall_seconds},
                      {"sim_time_ns", sim_time_ns(m)},
                      {"voxel_steps", m.counts.voxel_steps},
                      {"intersection_tests", m.counts.intersection_tests},
                      {"mac_products", m.mac_products},
                      {"mac_busy_cycles", m.mac_busy_cycles},
                      {"link_busy_cycles", whole_cycles(m.host.link_busy, c)},
                      {"load_imbalance", s.profile.imbalance},
                      {"bottleneck", s.bottleneck.name},
                      {"mac_bound_cycles", s.mac_bound_cycles},
                      {"cycles_over_mac_bound", s.cycles_over_mac_bound}};
  flatten_into(j, "error_", error_json(err));
  flatten_into(j, "rays_", rays_json(m.counts));
  flatten_into(j, "util_", utilisation_json(s.utilisation));
  flatten_into(j, "pe_util_", pe_utilisation_json(s.profile));
  flatten_into(j, "pe_issue_", utilisation_json(s.profile.issue));
  flatten_into(j, "pe_starved_", utilisation_json(s.profile.starved));
  flatten_into(j, "", phases_json(s.profile));
  flatten_into(j, "", cost_summary_json(cost));
  return j;
}

}  // namespace

nlohmann::json run_json(const std::vector<std::string>& command_line, const std::string& scene_path,
                        const std::string& scene_text) {
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", (unsigned long long)fnv1a(scene_text));
  const BuildInfo& b = build_info();
  return {{"schema_version", kStatsSchemaVersion},
          {"build",
           {{"version", b.version},
            {"commit", b.commit},
            {"modified", b.modified ? nlohmann::json(*b.modified) : nlohmann::json(nullptr)}}},
          {"command_line", command_line},
          {"scene_path", scene_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene_path)},
          {"scene_fnv1a", hash}};
}

nlohmann::json scene_json(const Scene& s, const Grid& g, double grid_seconds) {
  nlohmann::json skipped =
      nlohmann::json::array();  // what the reader left out (docs/scene-format.md)
  for (const SkippedRecords& k : s.skipped)
    skipped.push_back(
        {{"kind", k.kind}, {"reason", k.reason}, {"count", k.count}, {"lines", k.lines}});
  return {{"scene", s.name},
          {"skipped", skipped},
          {"width", s.camera.width},
          {"height", s.camera.height},
          {"primitives", s.primitives.size()},
          {"grid",
           {{"resolution", g.n}, {"references", g.items.size()}, {"build_seconds", grid_seconds}}},
          {"spawn", {{"offset", s.spawn_offset}, {"policy", to_string(s.spawn_policy)}}}};
}

nlohmann::json reference_render_json(const ReferenceResult& r) {
  nlohmann::json j = counts_json(r.counts);
  j["renderer"] = "reference";
  j["wall_seconds"] = r.wall_seconds;
  return j;
}

nlohmann::json machine_render_json(const MachineResult& m, const MachineConfig& c,
                                   const MachineCost& cost, const ImageError& err,
                                   const ErrorCauses& causes, const ReferenceResult& ref,
                                   bool ref_cached) {
  nlohmann::json j = counts_json(m.counts);
  j["renderer"] = "machine";
  j["wall_seconds"] = m.wall_seconds;
  j.update(machine_json(m, c));
  j["error"] = error_json(err);
  j["error"]["causes"] = causes_json(causes);
  j["cost"] = cost_json(cost);
  j["summary"] = summary_json(m, c, cost, err);
  // The same rays, walks and tests as the machine's: at fp64 always; at fp32 unless a hit flipped
  // (docs/machine.md, "Statistics").
  j["reference"] = {{"wall_seconds", ref.wall_seconds},
                    {"cached", ref_cached},
                    {"rays_match", ref.counts.rays == m.counts.rays},
                    {"counts_match", count_differences(m.counts, ref.counts).empty()}};
  return j;
}

}  // namespace rtm
