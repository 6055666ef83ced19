// --plugins DIR (repeatable) for the commands that read estimators (CONTRACT §2, §7). Each folder
// is added to the registry while the command line is parsed, before the command runs; the shipped
// examples and $AOEVAL_PLUGINS are read by the registry itself.
#pragma once

#include <CLI/CLI.hpp>

namespace aoeval {

void add_plugins_option(CLI::App* command);

}  // namespace aoeval
