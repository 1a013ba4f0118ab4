// Which build this is: the version, the commit the sources were at and whether they differed from
// it, from git at build time (cmake/build_info.cmake). `rtm --version` prints them and every stats
// file records them.
#pragma once

#include <optional>
#include <string>

namespace rtm {

struct BuildInfo {
  std::string version;
  std::string commit;            ///< the full hash; "unknown" outside a git checkout
  std::optional<bool> modified;  ///< tracked files differ from the commit; empty: unknown
};

const BuildInfo& build_info();

/// `rtm --version`'s line: "rtm 0.1 (commit 1a2b..., modified)".
std::string version_text();

}  // namespace rtm
