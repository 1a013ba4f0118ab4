#include "build_info.h"

namespace rtm {

std::string version_text() {
  const BuildInfo& b = build_info();
  const std::string state = !b.modified ? "" : *b.modified ? ", modified" : ", unmodified";
  return "rtm " + b.version + " (commit " + b.commit + state + ")";
}

}  // namespace rtm
