#include <sstream>

#include "machine/machine.h"
#include "render/image_io.h"

namespace rtm {

void write_gtkw(const std::string& gtkw_path, const std::string& vcd_path, const MachineConfig& c,
                const PeUnits& units, const std::vector<int>& pes) {
  std::ostringstream g;
  g << "[dumpfile] \"" << vcd_path << "\"\n[timestart] 0\n";
  auto group = [&](const std::string& title) { g << "@200\n-" << title << "\n"; };
  auto bit = [&](const std::string& s) { g << "@28\n" << s << "\n"; };
  auto dec = [&](const std::string& s) { g << "@24\n" << s << "\n"; };
  auto real = [&](const std::string& s) { g << "@800024\n" << s << "\n"; };
  for (int pe : pes) {
    const std::string p = "SystemC.machine.pe" + std::to_string(pe) + ".";  // the VCD scopes
    group("PE " + std::to_string(pe) + " front buffer");
    bit(p + "front_buffer.busy");
    dec(p + "front_buffer.ray_id[31:0]");
    dec(p + "front_buffer.waiting[31:0]");
    dec(p + "search_fifo.occupancy[31:0]");
    group("PE " + std::to_string(pe) + " search");
    for (int k = 0; k < c.search_units; ++k) {
      bit(p + "search" + std::to_string(k) + ".busy");
      dec(p + "search" + std::to_string(k) + ".ray_id[31:0]");
    }
    dec(p + "feedback_search.occupancy[31:0]");
    dec(p + "intersect_fifo.occupancy[31:0]");
    for (int k = 0; k < c.intersection_units; ++k) {
      const std::string x = p + "intersection" + std::to_string(k) + ".";
      group("PE " + std::to_string(pe) + " intersection unit " + std::to_string(k));
      bit(x + "mac.busy");
      dec(x + "mac.ray_id[31:0]");
      if (c.timing == Timing::Clocked) {
        const std::string m = x + "mac_unit.";
        bit(m + "m1_valid");
        real(m + "m1_a");
        real(m + "m1_b");
        real(m + "m1_out");
        bit(m + "m2_valid");
        real(m + "m2_coef");
        real(m + "m2_out");
        bit(m + "add_valid");
        real(m + "acc");
        dec(m + "product_counter[31:0]");
      }
      dec(x + "to_root.occupancy[31:0]");
      bit(x + "root.busy");
      dec(x + "root.ray_id[31:0]");
    }
    dec(p + "feedback_intersect.occupancy[31:0]");
    group("PE " + std::to_string(pe) + " shading");
    dec(p + "shade_fifo.occupancy[31:0]");
    bit(p + "shading.busy");
    dec(p + "shading.ray_id[31:0]");
    for (auto [kept, unit] : {std::pair<bool, const char*>{c.leave_out ? units.shadow_rays : true, "shadow_rays"},
                              {c.leave_out ? units.reflection : true, "reflection"},
                              {c.leave_out ? units.refraction : true, "refraction"}})
      if (kept) bit(p + "shading." + unit + ".busy");
    if (!c.leave_out || units.spawn_path) dec(p + "spawn_fifo.occupancy[31:0]");
    dec(p + "ends_fifo.occupancy[31:0]");
  }
  write_text_atomically(gtkw_path, g.str());
}

}  // namespace rtm
