// "Did you mean ...?": the known name closest to a mistyped one, by edit distance.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace rtm {

/// Insertions, deletions and substitutions that turn a into b (Levenshtein).
inline size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The name in `known` closest to `typed`, if it is close enough to be what was meant (at most
/// two edits, and fewer than a third of the name); else "".
inline std::string nearest_name(const std::string& typed, const std::vector<std::string>& known) {
  std::string best;
  size_t best_distance = std::min<size_t>(3, (typed.size() + 2) / 3);  // must be below this
  for (const std::string& k : known) {
    // The distance is at least the difference in length: a name that long cannot be near, and a
    // long typed name (a configuration file's 1 MB key) would cost its length times each name's.
    if (std::max(typed.size(), k.size()) - std::min(typed.size(), k.size()) >= best_distance)
      continue;
    if (const size_t d = edit_distance(typed, k); d < best_distance) {
      best = k;
      best_distance = d;
    }
  }
  return best;
}

}  // namespace rtm
