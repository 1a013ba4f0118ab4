// libFuzzer target: scripts/fuzz mesh (docs/reliability.md, "Fuzzing").
#include <cstddef>
#include <cstdint>

#include "fuzz/entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rtm::fuzz::mesh({reinterpret_cast<const char*>(data), size});
  return 0;
}
