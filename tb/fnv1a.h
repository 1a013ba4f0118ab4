// 64-bit FNV-1a: a content hash for names and checks (the reference cache's keys, the scene file
// the statistics record), not for security.
#pragma once

#include <cstdint>
#include <string_view>

namespace rtm {

inline constexpr uint64_t kFnvBasis = 1469598103934665603ull, kFnvPrime = 1099511628211ull;

inline uint64_t fnv1a(std::string_view s, uint64_t h = kFnvBasis) {
  for (unsigned char c : s) h = (h ^ c) * kFnvPrime;
  return h;
}

}  // namespace rtm
