// Process plug-ins: the protocol of plugin_process.h.
#include "estimators/plugins/plugin_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "base/errors.h"
#include "base/json_reader.h"
#include "base/version.h"
#include "scenes/exr_io.h"
#include "scenes/gbuffer.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

double ms_between(std::chrono::steady_clock::time_point a,
                  std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// In the child between fork and exec only async-signal-safe calls: write, dup2, chdir, execvp,
// _exit (strerrordesc_np returns a static string, no locale, no allocation).
void child_fail(const char* what, const char* arg) {
  const char* why = strerrordesc_np(errno);
  for (const char* s : {"aoeval: ", what, " '", arg, "': ", why ? why : "error", "\n"})
    if (write(2, s, std::strlen(s)) < 0) break;
  _exit(127);
}

// Waits for `pid` to end (without reaping it) at most `timeout_ms`; true when it ended. pidfd
// (Linux 5.3) gives an exact wake-up; without it, polling every millisecond.
bool wait_for_exit(pid_t pid, double timeout_ms) {
  const auto t0 = std::chrono::steady_clock::now();
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  bool ended = false;
  while (!ended) {
    const double left = timeout_ms - ms_between(t0, std::chrono::steady_clock::now());
    if (left <= 0.0) break;
    if (pidfd >= 0) {
      pollfd p{pidfd, POLLIN, 0};
      const int r = poll(&p, 1, static_cast<int>(std::ceil(std::min(left, 1e9))));
      if (r > 0) ended = true;
      if (r < 0 && errno != EINTR) break;
    } else {
      siginfo_t info{};
      if (waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
          info.si_pid == pid)
        ended = true;
      else
        usleep(1000);
    }
  }
  if (pidfd >= 0) close(pidfd);
  return ended;
}

// The leaders of the plug-in processes running now (another thread's plug-in is not an orphan).
std::mutex& leaders_mutex() {
  static std::mutex m;
  return m;
}
std::set<pid_t>& running_leaders() {
  static std::set<pid_t> leaders;
  return leaders;
}

// A plug-in's descendants can leave its process group (setsid) and, once their parent exits,
// would be adopted by init and outlive aoeval. As a child subreaper (prctl, Linux 3.4) aoeval
// adopts them instead, so that they can be found and killed: the descendants of the leader, and
// any adopted child of aoeval outside aoeval's own process group (aoeval's own helpers, the plot
// workers and popen's children, stay in its group).
void become_subreaper() {
  static std::once_flag once;
  std::call_once(once, [] { prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0); });
}

struct ProcStat {
  pid_t ppid = 0, pgid = 0;
  char state = '?';
};

std::map<pid_t, ProcStat> process_table() {
  std::map<pid_t, ProcStat> table;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t close_paren = text.rfind(')');  // the command name may hold ')' itself
    if (close_paren == std::string::npos) continue;
    std::istringstream fields(text.substr(close_paren + 1));
    ProcStat st;
    if (fields >> st.state >> st.ppid >> st.pgid) table[std::stoi(name)] = st;
  }
  return table;
}

// Kills (SIGKILL) and reaps every descendant of `leader` (0: none; never a reaped leader, whose id
// may be reused) and every orphan aoeval adopted, until a scan of /proc finds none alive: a
// process forking meanwhile is caught by the next round.
void kill_descendants(pid_t leader) {
  const pid_t self = getpid(), own_group = getpgrp();
  for (int round = 0; round < 1000; ++round) {
    const std::map<pid_t, ProcStat> table = process_table();
    std::set<pid_t> roots;
    if (leader > 0) roots.insert(leader);
    {
      std::lock_guard lock(leaders_mutex());
      for (const auto& [pid, st] : table)
        if (st.ppid == self && st.pgid != own_group && !running_leaders().count(pid))
          roots.insert(pid);
    }
    bool alive = false;
    for (const auto& [pid, st] : table) {
      bool target = roots.count(pid) > 0;
      // Walk up the parent chain (bounded: a cycle cannot occur, but the table is a snapshot).
      for (pid_t p = st.ppid; !target && p > 1 && p != self;) {
        if (roots.count(p)) target = true;
        const auto it = table.find(p);
        if (it == table.end()) break;
        p = it->second.ppid;
      }
      if (!target || pid == leader) continue;
      if (st.state != 'Z') {
        alive = true;
        kill(pid, SIGKILL);
      }
      if (st.ppid == self) waitpid(pid, nullptr, WNOHANG);
    }
    if (!alive) return;
    usleep(1000);
  }
}

float median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return static_cast<float>(n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

bool is_pass_name(const std::string& s) {
  if (s.empty() || s == "total" || s == "precompute" || s == "process" || s == "time") return false;
  if (!(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// AO.exr.timing.json -> pass_ms; "" or the reason it is rejected.
std::string read_timing(const std::string& path, EstimateResult& r) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = parse_json_text(text.str(), "AO.exr.timing.json");
  } catch (const InputError& e) {
    return e.what();  // "AO.exr.timing.json:1:15: invalid JSON (at key frame_ms[0])"
  }
  auto times = [](const nlohmann::json& a, std::vector<double>& out) {
    if (!a.is_array() || a.empty()) return false;
    for (const auto& v : a) {
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0) return false;
      out.push_back(v.get<double>());
    }
    return true;
  };
  std::vector<double> frames;
  if (!j.is_object() || !j.contains("frame_ms") || !times(j["frame_ms"], frames))
    return "AO.exr.timing.json: frame_ms must be a non-empty array of non-negative numbers";
  r.pass_ms["total_ms"] = median_of(frames);
  if (j.contains("passes_ms")) {
    if (!j["passes_ms"].is_object()) return "AO.exr.timing.json: passes_ms must be an object";
    for (const auto& [name, values] : j["passes_ms"].items()) {
      std::vector<double> v;
      if (!is_pass_name(name))
        return "AO.exr.timing.json: pass name \"" + name +
               "\" must be an identifier other than total, precompute, process and time";
      if (!times(values, v))
        return "AO.exr.timing.json: passes_ms." + name + " must be a non-empty array of numbers";
      r.pass_ms[name + "_ms"] = median_of(v);
    }
  }
  r.timing_source = "plugin-frames";
  return "";
}

std::string pixel_text(const GBuffer& g, size_t k) {
  // snprintf, not "(" + std::to_string(...): GCC 12 warns falsely (-Wrestrict) on the latter.
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%zu, %zu)", k % static_cast<size_t>(g.width),
                k / static_cast<size_t>(g.width));
  return buf;
}

}  // namespace

pid_t start_plugin_process(const std::vector<std::string>& argv, const std::string& cwd, int in_fd,
                           int out_fd, int err_fd, std::string& error) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  become_subreaper();
  std::unique_lock leaders_lock(leaders_mutex());  // registered before any scan can see it
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    // dup2 leaves the new descriptors without FD_CLOEXEC; every other one of ours closes on exec.
    if (dup2(in_fd, 0) < 0 || dup2(out_fd, 1) < 0 || dup2(err_fd, 2) < 0) _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);  // the program starts with no signal blocked
    if (chdir(cwd.c_str()) != 0) child_fail("cannot enter", cwd.c_str());
    execvp(args[0], args.data());
    child_fail("cannot run", args[0]);
  }
  if (pid > 0) running_leaders().insert(pid);
  leaders_lock.unlock();
  if (pid < 0) {
    error = std::string("cannot start a process: ") + std::strerror(errno);
    return -1;
  }
  setpgid(pid, pid);  // also here: whichever of parent and child runs first makes the group
  return pid;
}

bool wait_for_plugin_exit(pid_t pid, double timeout_ms) {
  return wait_for_exit(pid, timeout_ms);
}

void end_plugin_process(pid_t pid, ProcessOutcome& o) {
  // The leader is not reaped yet, so its id (the group's) cannot have been reused: kill the whole
  // group, on time-out and after a normal end alike (background children die with it).
  kill(-pid, SIGKILL);
  kill_descendants(pid);  // those that left the group (setsid) too
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  {
    std::lock_guard lock(leaders_mutex());
    running_leaders().erase(pid);
  }
  kill_descendants(0);  // reaps what the leader's end reparented meanwhile
  if (!o.timed_out) {
    if (WIFEXITED(status)) o.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
  }
}

std::string process_failure(const ProcessOutcome& o, double timeout_s) {
  if (!o.started) return o.error;
  if (o.timed_out)
    return "timed out after " + format_param_value(timeout_s) + " s (process group killed)";
  if (o.signal)
    return "killed by signal " + std::to_string(o.signal) + " (" + sigabbrev_np(o.signal) + ")";
  if (o.exit_code != 0) return "exited with status " + std::to_string(o.exit_code);
  return "";
}

ProcessOutcome run_process(const std::vector<std::string>& argv, const std::string& cwd,
                           double timeout_s, const std::string& stdout_path,
                           const std::string& stderr_path) {
  ProcessOutcome o;
  const int out_fd = open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  const int err_fd = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out_fd < 0 || err_fd < 0 || null_fd < 0) {
    o.error = std::string("cannot open its output files: ") + std::strerror(errno);
    for (int fd : {out_fd, err_fd, null_fd})
      if (fd >= 0) close(fd);
    return o;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = start_plugin_process(argv, cwd, null_fd, out_fd, err_fd, o.error);
  close(out_fd);
  close(err_fd);
  close(null_fd);
  if (pid < 0) return o;
  o.started = true;
  o.timed_out = !wait_for_exit(pid, timeout_s * 1000.0);
  end_plugin_process(pid, o);
  o.wall_ms = ms_between(t0, std::chrono::steady_clock::now());
  return o;
}

std::string last_line_of(const std::string& path) {
  // Only the file's last 64 KiB are read: a program may write gigabytes to stderr (or one endless
  // line), and its last words are at the end. A last line longer than that is cut at its start.
  constexpr std::streamoff kTail = 64 * 1024;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return "";
  const std::streamoff size = in.tellg();
  const std::streamoff start = size > kTail ? size - kTail : 0;
  in.seekg(start);
  std::string tail(static_cast<size_t>(size - start), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  tail.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  size_t end = tail.size();
  std::string last;
  while (end > 0 && last.empty()) {
    const size_t begin = tail.rfind('\n', end - 1);
    const size_t from = begin == std::string::npos ? 0 : begin + 1;
    last = tail.substr(from, end - from);
    while (!last.empty() && (last.back() == '\r' || last.back() == ' ')) last.pop_back();
    if (from == 0 && start > 0 && !last.empty()) last = "..." + last;  // cut by the 64 KiB window
    end = begin == std::string::npos ? 0 : begin;
  }
  if (last.size() > 300) last = last.substr(0, 297) + "...";
  return last;
}

std::string read_process_output(const std::string& ao_path, const GBuffer& g, bool bent,
                                EstimateResult& result) {
  std::error_code ec;
  if (!fs::exists(ao_path, ec)) return "wrote no AO.exr";
  auto in = OIIO::ImageInput::open(ao_path);
  if (!in) return "AO.exr is not an image OpenImageIO reads (" + OIIO::geterror() + ")";
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width != g.width || spec.height != g.height)
    return "AO.exr is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
           ", the G-buffer " + std::to_string(g.width) + "x" + std::to_string(g.height);
  std::vector<float> px(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()))
    return "AO.exr cannot be read (" + in->geterror() + ")";
  auto channel = [&](const std::string& name) {
    for (int c = 0; c < spec.nchannels; ++c)
      if (spec.channelnames[static_cast<size_t>(c)] == name) return c;
    return -1;
  };
  const int ao = channel("AO");
  if (ao < 0) return "AO.exr has no channel AO";
  const size_t nc = static_cast<size_t>(spec.nchannels), n = g.pixel_count();
  result.ao.assign(n, 0.0f);
  for (size_t k = 0; k < n; ++k) {
    if (!g.covered(k)) continue;
    const float v = px[k * nc + static_cast<size_t>(ao)];
    if (!std::isfinite(v))
      return std::string("AO is ") + (std::isnan(v) ? "NaN" : "infinite") + " at covered pixel " +
             pixel_text(g, k);
    if (v < -kAoRangeSlack || v > 1.0f + kAoRangeSlack)
      return "AO = " + format_param_value(v) + " at covered pixel " + pixel_text(g, k) +
             " is outside [0, 1]";
    result.ao[k] = std::clamp(v, 0.0f, 1.0f);
  }
  if (bent) {
    for (const char* axis : {"X", "Y", "Z"}) {
      const std::string name = std::string("bent.") + axis;
      const int c = channel(name);
      if (c < 0) return "AO.exr has no channel " + name + " (estimator.json's outputs hold bent)";
      std::vector<float>& out = result.extra_channels[name];
      out.assign(n, 0.0f);
      for (size_t k = 0; k < n; ++k) {
        if (!g.covered(k)) continue;
        out[k] = px[k * nc + static_cast<size_t>(c)];
        if (!std::isfinite(out[k]))
          return name + " is not finite at covered pixel " + pixel_text(g, k);
      }
    }
  }
  const std::string timing = ao_path + ".timing.json";
  if (fs::exists(timing, ec)) return read_timing(timing, result);
  return "";
}

PluginFolder::~PluginFolder() {
  std::error_code ignored;
  if (!path_.empty()) fs::remove_all(path_, ignored);
}

void PluginFolder::write_inputs(const EstimateContext& context, const nlohmann::json& params) {
  if (path_.empty()) {
    std::string pattern = (fs::temp_directory_path() / "aoeval-plugin-XXXXXX").string();
    if (!mkdtemp(pattern.data()))
      throw std::runtime_error("plug-in " + name_ + ": cannot make a folder " + pattern + ": " +
                               std::strerror(errno));
    path_ = pattern;
  }
  const GBuffer& g = context.gbuffer;
  write_exr(path_ + "/G.exr", gbuffer_to_image(g),
            {{"aoeval:scene", context.scene.name},
             {"aoeval:camera", camera_to_json(g.camera)},
             {"aoeval:version", kAoevalVersion}});
  write_text(path_ + "/P.json", params.dump(2) + "\n");
}

namespace {

class ProcessEstimator : public Estimator {
 public:
  ProcessEstimator(PluginManifest m, ParamSet params)
      : manifest_(std::move(m)), params_(std::move(params)), folder_(manifest_.name) {}

  void prepare(const EstimateContext& context) override {
    folder_.write_inputs(context, params_.json());
    dir_ = folder_.path();
    prepared_for_ = &context.gbuffer;
  }

  EstimateResult run(const EstimateContext& context) override {
    if (prepared_for_ != &context.gbuffer) prepare(context);
    const std::string ao = dir_ + "/AO.exr", out = dir_ + "/stdout.txt", err = dir_ + "/stderr.txt";
    std::error_code ec;
    for (const std::string& f : {ao, ao + ".timing.json", out, err}) fs::remove(f, ec);
    std::vector<std::string> argv = manifest_.command;
    for (const std::string& a :
         {std::string("--gbuffer"), dir_ + "/G.exr", std::string("--params"), dir_ + "/P.json",
          std::string("--out"), ao, std::string("--frames"), std::to_string(manifest_.frames)})
      argv.push_back(a);
    const ProcessOutcome o = run_process(argv, manifest_.folder, manifest_.timeout_s, out, err);
    std::string reason = process_failure(o, manifest_.timeout_s);
    EstimateResult r;
    if (reason.empty()) reason = read_process_output(ao, context.gbuffer, manifest_.bent, r);
    for (const std::string& f : {ao, ao + ".timing.json"}) fs::remove(f, ec);
    if (!reason.empty() && context.frame)  // a sequence: which frame (run once per frame)
      reason += " (frame " + std::to_string(context.frame->index) + ")";
    if (!reason.empty()) {
      const std::string last = last_line_of(err);
      throw EstimatorUnavailable("plug-in " + manifest_.name + " " + reason +
                                 (last.empty() ? " (stderr empty)" : ": " + last));
    }
    if (r.timing_source.empty()) {
      r.pass_ms["total_ms"] = o.wall_ms;
      r.timing_source = "process-wall";
    }
    r.pass_ms["process_ms"] = o.wall_ms;
    return r;
  }

 private:
  PluginManifest manifest_;
  ParamSet params_;
  PluginFolder folder_;
  std::string dir_;
  const GBuffer* prepared_for_ = nullptr;
};

}  // namespace

std::unique_ptr<Estimator> make_process_estimator(const PluginManifest& m, const ParamSet& params) {
  return std::make_unique<ProcessEstimator>(m, params);
}

}  // namespace aoeval
