// `rtm config`: every machine configuration key with its value and meaning.
#include <iostream>

#include "options.h"
#include "render_options.h"

namespace rtm {

int run_config(const std::string& config_file, const std::vector<std::string>& sets) {
  RenderOptions opt;
  opt.config_file = config_file;
  opt.sets = sets;
  return run_command([&] {
    std::cout << describe_config(machine_config(opt));
    return 0;
  });
}

}  // namespace rtm
