#include "cmd/plugin_options.h"

#include <string>
#include <vector>

#include "estimators/registry.h"

namespace aoeval {

void add_plugins_option(CLI::App* command) {
  command->add_option_function<std::vector<std::string>>(
      "--plugins",
      [](const std::vector<std::string>& dirs) {
        for (const auto& d : dirs) add_plugin_dir(d);
      },
      "plug-in estimator folder, or a folder of them (repeatable; also $AOEVAL_PLUGINS, "
      "':'-separated)");
}

}  // namespace aoeval
