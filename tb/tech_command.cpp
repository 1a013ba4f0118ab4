// `rtm tech [FILE]`: every entry of a technology with its value, unit and source.
#include <iostream>

#include "cost/technology.h"
#include "options.h"
#include "render_options.h"

namespace rtm {

int run_tech(const std::string& file, bool markdown) {
  return run_command([&] {
    if (markdown) {
      std::cout << technology_entries_markdown();
      return 0;
    }
    std::cout << describe_technology(technology(file.empty() ? kBuiltInTechnology : file));
    return 0;
  });
}

}  // namespace rtm
