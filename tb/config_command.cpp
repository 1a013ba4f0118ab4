// `rtm config`: every machine configuration key with its value and meaning, or the docs' tables.
#include <iostream>

#include "options.h"
#include "render_options.h"

namespace rtm {

int run_config(const RenderOptions& opt, bool markdown) {
  return run_command([&] {
    const MachineConfig c = machine_config(opt);  // a bad preset is a usage error here too
    if (!markdown)
      std::cout << describe_config(c);
    else if (opt.preset.empty())
      std::cout << config_keys_markdown();
    else
      std::cout << preset_markdown(c.preset);
    return 0;
  });
}

}  // namespace rtm
