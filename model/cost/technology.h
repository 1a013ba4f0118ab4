// A technology: the energy per operation and the area of the datapath elements a PE is built
// from, each with the published source it comes from, read from a YAML technology file
// (model/cost/tech/45nm.yaml, docs/cost.md). Plain C++: no SystemC. What each entry means, its
// unit and how a derived node scales it are declared once, in technology_entries().
#pragma once

#include <string>
#include <vector>

#include "config/config.h"
#include "scene/file_error.h"

namespace rtm {

/// A bad technology file: "file:line: what is wrong". Like a bad configuration, the user's
/// input is at fault (rtm exits 2).
struct TechnologyError : FileError {
  using FileError::FileError;
};

/// One figure of the table, and where it comes from.
struct TechValue {
  double value = 0;
  std::string source;
};

struct Technology {
  std::string name;  ///< "45nm"
  std::string file;  ///< where it was read from ("<built-in 45nm>" for the compiled-in file)

  // Energy per operation (pJ) and area (µm²) of each arithmetic element.
  TechValue int32_add_pj, int32_add_um2, int32_compare_pj, int32_compare_um2;
  TechValue fp32_add_pj, fp32_add_um2, fp32_mul_pj, fp32_mul_um2, fp32_compare_pj, fp32_compare_um2;
  TechValue fp32_div_pj, fp32_div_um2, fp32_sqrt_pj, fp32_sqrt_um2;
  TechValue fp64_add_pj, fp64_add_um2, fp64_mul_pj, fp64_mul_um2, fp64_compare_pj, fp64_compare_um2;
  TechValue fp64_div_pj, fp64_div_um2, fp64_sqrt_pj, fp64_sqrt_um2;
  // A register or FIFO bit.
  TechValue register_bit_write_pj, register_bit_um2;
  // On-chip SRAM: an access of a word of sram_word_bits in an SRAM of sram_bytes costs
  // sram_access_pj; other sizes follow sram_access_energy_pj().
  TechValue sram_access_pj, sram_bytes, sram_word_bits, sram_energy_exponent, sram_bit_um2;
  // Off-chip DRAM (a PE's local memory) and the host-PE link.
  TechValue dram_read_bit_pj, dram_write_bit_pj, dram_bit_um2, link_bit_pj;
  // Leakage.
  TechValue logic_leakage_nw_per_um2, sram_leakage_pw_per_bit;
};

/// How a derived node (scale_from:) changes an entry: by the file's energy, area or leakage
/// factor, or not at all (sizes and exponents).
enum class TechScaling { Energy, Area, Leakage, None };

/// One entry of the technology file, declared once: `rtm tech`, the parser and docs/cost.md read
/// it.
struct TechEntry {
  const char* name;
  const char* unit;
  const char* meaning;
  TechScaling scaling;
  bool positive;  ///< the value must be > 0 (else >= 0)
  TechValue Technology::*member;
};
const std::vector<TechEntry>& technology_entries();

/// The name of the compiled-in technology (model/cost/tech/45nm.yaml), the `tech` key's default.
inline constexpr const char* kBuiltInTechnology = "45nm";

/// Reads a technology: the built-in one by its name, else the YAML file at `spec`. A file with
/// `scale_from: BASE` (a file beside it, or the built-in name) takes BASE's entries times its
/// `factors`, and then its own entries. Throws TechnologyError.
Technology load_technology(const std::string& spec);
/// The same from a file's text; `file` names it in messages and locates its scale_from.
Technology parse_technology(const std::string& text, const std::string& file);

/// Energy of one access (read or write) of a word of `word_bits` in an SRAM of `capacity_bytes`:
/// linear in the bits moved, and capacity^sram_energy_exponent (docs/cost.md says the fit).
double sram_access_energy_pj(const Technology& t, double capacity_bytes, double word_bits);
/// Area of an SRAM of `capacity_bytes`: its bits times sram_bit_um2 (cell and periphery).
double sram_area_um2(const Technology& t, double capacity_bytes);
/// Energy of one MAC product (a multiply and the accumulating add) in the given arithmetic.
double mac_product_energy_pj(const Technology& t, Precision p);

/// Every entry: name, value, unit and source, one a line, as `rtm tech` prints it.
std::string describe_technology(const Technology& t);
/// docs/cost.md's table of the entries: name, unit, meaning, how a derived node scales it.
std::string technology_entries_markdown();

}  // namespace rtm
