// The SRAM model (docs/cost.md, "SRAM") against published sizes its fit does not use.
//
// The model's size dependence, energy ∝ capacity^0.5 and area ∝ capacity, is fitted to
// Horowitz's 8 KB and 32 KB reads (ISSCC 2014; technology_test.cpp checks his 1 MB read). Here it
// is compared with a CACTI table of another group: SimTRaX's data-cache parameters
// (github.com/dkoptacs/simtrax, samples/configs/dcacheparams.txt, commit 2144cb2f, 2014; the
// repository's configurations are 65 nm; the table gives area in mm² and energy per access in nJ
// for caches of 1 KB to 8 MB). The rows used are its single-bank, 32-byte-line ones. The node, the
// 32-byte line and the cache's tags differ from the model's 64-bit SRAM read, so what is compared
// is each size against the table's 32 KB, the top of the model's fit: ratios, which the node and
// the line width scale alike. The misses are asserted too, so the range docs/cost.md states stays
// true.

#include <cmath>

#include <gtest/gtest.h>

#include "cost/technology.h"

namespace rtm {
namespace {

struct CactiRow {
  double bytes, area_mm2, energy_nj;
};

// samples/configs/dcacheparams.txt, rows "SIZE 1 32" (one bank, 32-byte lines).
constexpr CactiRow kCacti[] = {
    {1 << 10, 0.045308, 0.057741},   {2 << 10, 0.053354, 0.062755},
    {4 << 10, 0.074405, 0.072801},   {8 << 10, 0.109827, 0.092133},
    {16 << 10, 0.211103, 0.127154},  {32 << 10, 0.328905, 0.169293},
    {64 << 10, 0.656136, 0.237390},  {128 << 10, 1.271121, 0.324096},
    {256 << 10, 2.586821, 0.461716}, {512 << 10, 4.854572, 0.646135},
    {1 << 20, 11.650170, 0.912311},  {2 << 20, 18.893860, 1.174851},
    {4 << 20, 37.714440, 1.661012},  {8 << 20, 73.361190, 2.190471},
};
constexpr CactiRow kReference = kCacti[5];  // 32 KB

/// The model's ratio against the table's, minus one: +0.1 is a model 10 % above.
double energy_error(const Technology& t, const CactiRow& r) {
  const double model =
      sram_access_energy_pj(t, r.bytes, 64) / sram_access_energy_pj(t, kReference.bytes, 64);
  return model / (r.energy_nj / kReference.energy_nj) - 1;
}

double area_error(const Technology& t, const CactiRow& r) {
  const double model = sram_area_um2(t, r.bytes) / sram_area_um2(t, kReference.bytes);
  return model / (r.area_mm2 / kReference.area_mm2) - 1;
}

TEST(SramValidation, EnergyFollowsCactiWithin20PercentFrom4KBTo4MB) {
  const Technology t = load_technology(kBuiltInTechnology);
  for (const CactiRow& r : kCacti) {
    const double e = energy_error(t, r);
    if (r.bytes >= (4 << 10) && r.bytes <= (4 << 20))
      EXPECT_LT(std::abs(e), 0.20) << r.bytes << " bytes: model " << 100 * e << " %";
    else  // 1 KB -48 %, 2 KB -33 % (a fixed decoder and sense cost the power law leaves out); 8 MB
          // +24 %
      EXPECT_GT(std::abs(e), 0.20) << r.bytes << " bytes: model " << 100 * e << " %";
  }
}

TEST(SramValidation, AreaFollowsCactiWithin20PercentFrom32KBTo8MB) {
  const Technology t = load_technology(kBuiltInTechnology);
  for (const CactiRow& r : kCacti) {
    const double e = area_error(t, r);
    if (r.bytes >= (32 << 10))
      EXPECT_LT(std::abs(e), 0.20) << r.bytes << " bytes: model " << 100 * e << " %";
    else  // 16 KB -22 % ... 1 KB -77 %: a small array's periphery does not shrink with it
      EXPECT_GT(std::abs(e), 0.20) << r.bytes << " bytes: model " << 100 * e << " %";
  }
}

}  // namespace
}  // namespace rtm
