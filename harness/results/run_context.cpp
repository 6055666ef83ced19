// The run context (RunContext, results_store.h): which machine, device, Embree, commit and time a
// run's rows share, probed once per run.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "base/summary.h"
#include "harness/results/results_store.h"

#if __has_include(<embree3/rtcore_config.h>)
#include <embree3/rtcore_config.h>
#endif
#if __has_include("version.h")
#include "base/version.h"
#endif

namespace aoeval {

// ---------------------------------------------------------------- run context

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const size_t begin = line.find_first_not_of(" \t", colon + 1);
    return begin == std::string::npos ? "unknown CPU" : line.substr(begin);
  }
  return "unknown CPU";
}

std::string git_commit() {
#ifdef AOEVAL_SOURCE_DIR
  std::string dir = AOEVAL_SOURCE_DIR, quoted = "'";
  for (char c : dir) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  FILE* pipe = popen(("git -C " + quoted + " rev-parse HEAD 2>/dev/null").c_str(), "r");
  if (!pipe) return "unknown";
  char buffer[128] = {};
  std::string out = std::fgets(buffer, sizeof buffer, pipe) ? buffer : "";
  pclose(pipe);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  const bool hex =
      out.size() >= 40 && out.find_first_not_of("0123456789abcdef") == std::string::npos;
  return hex ? out : "unknown";
#else
  return "unknown";
#endif
}

}  // namespace

RunContext make_run_context(const std::string& command) {
  RunContext c;
  char suffix[8];
  std::snprintf(suffix, sizeof suffix, "%06x", std::random_device{}() & 0xffffffu);
  c.run_id = utc_now("%Y%m%dT%H%M%SZ") + "-" + suffix;
  c.command = command;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "unknown-host");
  const std::string cpu = cpu_model();
  c.machine = std::string(host) + " (" + cpu + ", " +
              std::to_string(std::thread::hardware_concurrency()) + " cores)";
  c.device = cpu;
#ifdef RTC_VERSION_STRING
  c.embree_version = RTC_VERSION_STRING;
#else
  c.embree_version = "unknown";
#endif
  c.git_commit = git_commit();
#if __has_include("version.h")
  c.aoeval_version = kAoevalVersion;
#elif defined(AOEVAL_VERSION)
  c.aoeval_version = AOEVAL_VERSION;
#else
  c.aoeval_version = "unknown";
#endif
  c.started = utc_now("%Y-%m-%dT%H:%M:%SZ");
  return c;
}

nlohmann::json to_json(const RunContext& c) {
  nlohmann::json j = {{"run_id", c.run_id},
                      {"command", c.command},
                      {"machine", c.machine},
                      {"device", c.device},
                      {"embree_version", c.embree_version},
                      {"git_commit", c.git_commit},
                      {"aoeval_version", c.aoeval_version},
                      {"started", c.started},
                      {"output_dir", c.output_dir}};
  if (!c.stages_ms.empty()) j["stages_ms"] = c.stages_ms;
  return j;
}

RunContext run_context_from_json(const nlohmann::json& j) {
  auto s = [&](const char* key) { return j.is_object() ? j.value(key, std::string()) : ""; };
  RunContext c{s("run_id"),         s("command"),        s("machine"),
               s("device"),         s("embree_version"), s("git_commit"),
               s("aoeval_version"), s("started"),        s("output_dir")};
  if (j.is_object() && j.contains("stages_ms") && j["stages_ms"].is_object())
    c.stages_ms = j["stages_ms"];
  return c;
}

}  // namespace aoeval
