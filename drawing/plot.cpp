#include "drawing/plot.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "base/text_files.h"
#include "drawing/plot_workers.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace {

nlohmann::json to_json(const PlotSeries& s) {
  nlohmann::json j = {{"label", s.label}, {"kind", s.kind}, {"x", s.x}, {"y", s.y}};
  if (!s.y_error.empty()) j["y_error"] = s.y_error;
  if (!s.highlight.empty()) j["highlight"] = s.highlight;
  if (!s.point_labels.empty()) j["point_labels"] = s.point_labels;
  if (!s.colour.empty()) j["colour"] = s.colour;
  if (!s.marker.empty()) j["marker"] = s.marker;
  j["dashed"] = s.dashed;
  return j;
}

nlohmann::json to_json(const PlotSpec& p) {
  nlohmann::json series = nlohmann::json::array();
  for (const auto& s : p.series) series.push_back(to_json(s));
  nlohmann::json j = {
      {"title", p.title},         {"x_label", p.x_label}, {"y_label", p.y_label},
      {"log_x", p.log_x},         {"log_y", p.log_y},     {"categories", p.categories},
      {"series", series},         {"notes", p.notes},     {"width_in", p.width_in},
      {"height_in", p.height_in}, {"dpi", p.dpi}};
  if (!p.panels.empty()) {
    j["panels"] = nlohmann::json::array();
    for (const auto& panel : p.panels) j["panels"].push_back(to_json(panel));
  }
  return j;
}

void check_lengths(const PlotSpec& p) {
  for (const auto& panel : p.panels) check_lengths(panel);
  for (const auto& s : p.series) {
    const size_t n = s.y.size();
    if (s.x.size() != n || (!s.y_error.empty() && s.y_error.size() != n) ||
        (!s.highlight.empty() && s.highlight.size() != n) ||
        (!s.point_labels.empty() && s.point_labels.size() != n))
      throw std::runtime_error(std::string("plot '") + p.title + "': series '" + s.label +
                               "' has arrays of different lengths");
  }
}

// Draws the plots (specs already written) with a python process of its own.
void render_in_new_process(const std::vector<std::pair<std::string, std::string>>& jobs) {
  std::vector<std::string> args = {plot_python(), plot_script()};
  for (const auto& [spec_path, out_path] : jobs) {
    args.push_back(spec_path);
    args.push_back(out_path);
  }

  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // plot.py writes to a temporary name in the same folder and renames, so the image is atomic too.
  const std::string& first_out = jobs.front().second;
  // The log is a temporary of <image>.plot.log (base/text_files.h): what a killed run leaves is
  // removed by the next one's remove_stale_temporaries, never taken for a file of the run.
  const std::string log_path = temporary_path_for(first_out + ".plot.log");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("render_plot: fork failed");
  if (pid == 0) {
    FILE* log = std::fopen(log_path.c_str(), "w");
    if (log) {
      dup2(fileno(log), STDOUT_FILENO);
      dup2(fileno(log), STDERR_FILENO);
    }
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "cannot run %s\n", argv[0]);
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  std::string log_text;
  {
    std::ifstream in(log_path);
    std::stringstream ss;
    ss << in.rdbuf();
    log_text = ss.str();
  }
  discard_temporary(log_path);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    while (!log_text.empty() && (log_text.back() == '\n' || log_text.back() == '\r'))
      log_text.pop_back();
    const auto last_line = log_text.substr(
        log_text.find_last_of('\n') == std::string::npos ? 0 : log_text.find_last_of('\n') + 1);
    throw std::runtime_error(
        std::string("plot ") + first_out +
        (jobs.size() > 1 ? std::string(" (and ") + std::to_string(jobs.size() - 1) + " more)"
                         : std::string()) +
        ": " + plot_python() + " " + plot_script() +
        " failed: " + (last_line.empty() ? std::string("no output") : last_line));
  }
}

}  // namespace

std::string plot_script() {
  if (const char* env = std::getenv("AOEVAL_PLOT_SCRIPT")) return env;
  return std::string(AOEVAL_SOURCE_DIR) + "/drawing/plot.py";
}

std::string plot_python() {
  if (const char* env = std::getenv("AOEVAL_PYTHON"); env && *env) return env;
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

void render_plot(const PlotSpec& spec, const std::string& out_path) {
  render_plots({{spec, out_path}});
}

void render_plots(const std::vector<std::pair<PlotSpec, std::string>>& plots) {
  if (plots.empty()) return;
  std::vector<std::pair<std::string, std::string>> jobs;  // (spec path, image path)
  for (const auto& [spec, out_path] : plots) {
    check_lengths(spec);
    const std::string spec_path = out_path + ".plot.json";
    write_text(spec_path, to_json(spec).dump(1) + "\n");
    jobs.emplace_back(spec_path, out_path);
  }
  // A pre-started worker when one is idle (drawing/plot_workers.h); what it cannot draw (it
  // died) goes to a process of its own.
  size_t done = 0;
  PlotWorkers& pool = PlotWorkers::instance();
  if (PlotWorkers::Worker* worker = pool.acquire()) {
    try {
      while (done < jobs.size() && PlotWorkers::draw(*worker, jobs[done].first, jobs[done].second))
        ++done;
    } catch (...) {
      pool.release(worker);
      throw;
    }
    pool.release(worker);
  }
  if (done < jobs.size())
    render_in_new_process({jobs.begin() + static_cast<std::ptrdiff_t>(done), jobs.end()});
}

void render_plots_on_every_core(const std::vector<std::pair<PlotSpec, std::string>>& plots) {
  const size_t workers =
      std::min<size_t>(plots.size(), std::max(1u, std::thread::hardware_concurrency()));
  if (workers <= 1) return render_plots(plots);
  std::vector<std::vector<std::pair<PlotSpec, std::string>>> batches(workers);
  for (size_t i = 0; i < plots.size(); ++i) batches[i % workers].push_back(plots[i]);
  std::mutex mutex;
  std::string failure;
  std::vector<std::thread> threads;
  for (const auto& batch : batches)
    threads.emplace_back([&] {
      try {
        render_plots(batch);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mutex);
        if (failure.empty()) failure = e.what();
      }
    });
  for (auto& t : threads) t.join();
  if (!failure.empty()) throw std::runtime_error(failure);
}

}  // namespace aoeval
