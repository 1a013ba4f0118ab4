// Random MAC jobs for the clock-level MAC's tests, and the sums the schedule gives them.
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "units/clock_level_mac.h"

namespace rtm {

/// A random job of n primitives in precision p; sparse: random coefficient words zero and their
/// products skipped. Its per-primitive product counts go to `counts`.
inline MacJob random_job(std::mt19937_64& rng, int n, Precision p, bool sparse,
                         std::vector<int>& counts) {
  std::uniform_real_distribution<double> u(-3, 3);
  MacJob job;
  counts.clear();
  for (int k = 0; k < n; ++k) {
    Latches<double> l{};
    for (int i = 0; i < 6; ++i) {
      const double x = u(rng);  // one draw a statement: the order of draws is then defined
      l[size_t(i)] = round_to(p, x * std::pow(10.0, u(rng)));
    }
    l[kOne] = 1;
    CoefRam<double> ram{};
    for (int w = 0; w < kRamWords; ++w)
      ram[size_t(w)] = (sparse && rng() % 2) ? 0.0 : round_to(p, u(rng));
    if (sparse && ram == CoefRam<double>{}) ram[kRamJ] = 1;  // at least one product
    ram[kRam2A] = 2 * ram[kRamA];
    ram[kRam2B] = 2 * ram[kRamB];
    ram[kRam2C] = 2 * ram[kRamC];
    job.latches.push_back(l);
    job.rams.push_back(ram);
    if (sparse) job.ops.push_back(sparse_ops(ram));
    counts.push_back(sparse ? int(job.ops.back().size()) : kMacProducts);
  }
  return job;
}

/// The schedule's sums of primitive k, in the job's precision.
inline std::array<double, 3> expected_sums(const MacJob& job, size_t k, Precision p) {
  if (p == Precision::Fp32) {
    Latches<float> lf{};
    CoefRam<float> rf{};
    for (int i = 0; i < 7; ++i) lf[size_t(i)] = float(job.latches[k][size_t(i)]);
    for (int w = 0; w < kRamWords; ++w) rf[size_t(w)] = float(job.rams[k][size_t(w)]);
    const Abg<float> a = form_abg(lf, rf);
    return {a.a, a.b, a.g};
  }
  const Abg<double> a = form_abg(job.latches[k], job.rams[k]);
  return {a.a, a.b, a.g};
}

}  // namespace rtm
