// aoeval: one binary, one subcommand per job (CONTRACT §2). This file only parses the command line
// and maps failures to exit codes: 0 success, 2 bad usage or bad input, 1 anything else.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>

#include "base/errors.h"
#include "cmd/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"aoeval: benchmark and accuracy evaluation of ambient-occlusion estimators"};
  app.require_subcommand(1);
  app.option_defaults()->always_capture_default();  // --help shows every default
  app.set_version_flag("--version", "aoeval " + std::string(AOEVAL_VERSION));
  aoeval::add_scenes_command(app);
  aoeval::add_gbuffer_command(app);
  aoeval::add_estimators_command(app);
  aoeval::add_reference_command(app);
  aoeval::add_estimate_command(app);
  aoeval::add_compare_command(app);
  aoeval::add_sweep_command(app);
  aoeval::add_bench_command(app);
  aoeval::add_run_command(app);
  aoeval::add_figures_command(app);
  aoeval::add_dashboard_command(app);
  aoeval::add_tune_command(app);
  aoeval::add_merge_command(app);
  // CLI11 reports an unknown first word only as "a subcommand is required": name it, and the
  // commands there are.
  const std::string first = argc > 1 ? argv[1] : "";
  const std::function<bool(CLI::App*)> named = [&first](CLI::App* s) {
    return s->check_name(first);
  };
  if (!first.empty() && first[0] != '-' && app.get_subcommands(named).empty()) {
    std::string known;
    for (const CLI::App* sub : app.get_subcommands(std::function<bool(CLI::App*)>()))
      known.append(known.empty() ? "" : ", ").append(sub->get_name());
    std::fprintf(stderr, "aoeval: error: unknown command '%s' (commands: %s; see --help)\n",
                 argv[1], known.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "aoeval: error: %s (see --help)\n", e.what());
    return 2;
  } catch (const aoeval::ExitStatus& e) {
    return e.code;
  } catch (const aoeval::InputError& e) {
    std::fprintf(stderr, "aoeval: error: %s\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the user gave that cannot be read or written (a folder where a file belongs, no
    // permission, a symlink loop): bad input, named by its path.
    std::fprintf(stderr, "aoeval: error: %s: %s\n", e.path1().string().c_str(),
                 e.code().message().c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aoeval: failure: %s\n", e.what());
    return 1;
  }
  return 0;
}
