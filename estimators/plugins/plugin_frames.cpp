// The "protocol": "frames" process plug-in of plugin_frames.h.
#include "estimators/plugins/plugin_frames.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "estimators/plugins/plugin_process.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A line of someone else's program for a message: at most 120 characters, control bytes as '?'.
std::string quote_line(const std::string& line) {
  std::string s = line.size() > 120 ? line.substr(0, 117) + "..." : line;
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';
  return "'" + s + "'";
}

class FramesProcessEstimator : public Estimator {
 public:
  FramesProcessEstimator(PluginManifest m, ParamSet params)
      : manifest_(std::move(m)), params_(std::move(params)), folder_(manifest_.name) {}
  ~FramesProcessEstimator() override { stop(/*graceful=*/true); }

  // The frame's files, and the program when it is not running (its fork and exec are then this
  // frame's precompute time; its own start-up is in the first answer's).
  void prepare(const EstimateContext& context) override {
    folder_.write_inputs(context, frame_param_values(manifest_, params_.json(), context.frame));
    prepared_for_ = &context.gbuffer;
    prepared_frame_ = frame_of(context);
    if (pid_ < 0 && start_error_.empty()) start();
  }

  EstimateResult run(const EstimateContext& context) override {
    const int k = frame_of(context);
    if (prepared_for_ != &context.gbuffer || prepared_frame_ != k || pid_ < 0) prepare(context);
    const std::string dir = folder_.path(), ao = dir + "/AO.exr";
    if (pid_ < 0) {
      const std::string why = start_error_;
      start_error_.clear();  // the next run tries again
      fail(why);
    }
    std::error_code ec;
    for (const std::string& f : {ao, ao + ".timing.json"}) fs::remove(f, ec);
    const std::string between = drain();
    if (!between.empty())
      fail("wrote " + quote_line(between) +
           " to stdout between frames (stdout carries only the "
           "answers; write anything else to stderr)");
    const nlohmann::json request = {
        {"frame", k}, {"gbuffer", dir + "/G.exr"}, {"params", dir + "/P.json"}, {"out", ao}};
    const auto t0 = std::chrono::steady_clock::now();
    if (!send_line(request.dump() + "\n"))
      fail(ended_reason("before reading frame " + std::to_string(k)));
    std::string line;
    const std::string wait_error = read_line(k, line);
    const double wall = ms_since(t0);
    if (!wait_error.empty()) fail(wait_error);
    const std::string answer_error = check_answer(k, line);
    if (!answer_error.empty()) fail(answer_error);
    EstimateResult r;
    const std::string output_error = read_process_output(ao, context.gbuffer, manifest_.bent, r);
    for (const std::string& f : {ao, ao + ".timing.json"}) fs::remove(f, ec);
    if (!output_error.empty()) fail(output_error + " (frame " + std::to_string(k) + ")");
    if (r.timing_source.empty()) {
      r.pass_ms["total_ms"] = wall;
      r.timing_source = "frame-wall";
    }
    r.pass_ms["process_ms"] = wall;
    return r;
  }

 private:
  static int frame_of(const EstimateContext& context) {
    return context.frame ? context.frame->index : 0;
  }

  void start() {
    const std::string err = folder_.path() + "/stderr.txt";
    int ends[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) {
      start_error_ = std::string("cannot make its socket: ") + std::strerror(errno);
      return;
    }
    const int err_fd = open(err.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    if (err_fd < 0) {
      start_error_ = std::string("cannot open its stderr file: ") + std::strerror(errno);
      close(ends[0]);
      close(ends[1]);
      return;
    }
    pid_ = start_plugin_process(manifest_.command, manifest_.folder, ends[1], ends[1], err_fd,
                                start_error_);
    close(ends[1]);
    close(err_fd);
    if (pid_ < 0) {
      close(ends[0]);
      return;
    }
    socket_ = ends[0];
    pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
    buffer_.clear();
  }

  // Ends the program: graceful = EOF on its stdin and kFramesExitGraceS to exit first. Fills
  // `o` with how it ended (timed_out when it was still running and had to be killed).
  void stop(bool graceful, ProcessOutcome* o = nullptr) {
    if (pid_ < 0) return;
    ProcessOutcome ended;
    ended.started = true;
    if (graceful) shutdown(socket_, SHUT_WR);
    ended.timed_out =
        !(graceful ? wait_for_plugin_exit(pid_, kFramesExitGraceS * 1000.0) : exited());
    end_plugin_process(pid_, ended);
    close(socket_);
    if (pidfd_ >= 0) close(pidfd_);
    pid_ = -1;
    socket_ = pidfd_ = -1;
    if (o) *o = ended;
  }

  [[noreturn]] void fail(const std::string& reason) {
    stop(/*graceful=*/false);
    const std::string last = last_line_of(folder_.path() + "/stderr.txt");
    throw EstimatorUnavailable("plug-in " + manifest_.name + " " + reason +
                               (last.empty() ? " (stderr empty)" : ": " + last));
  }

  bool exited() const {
    if (pidfd_ >= 0) {
      pollfd p{pidfd_, POLLIN, 0};
      return poll(&p, 1, 0) > 0;
    }
    siginfo_t info{};
    return waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
           info.si_pid == pid_;
  }

  // How the program ended, when it did: "exited with status 3 <when>", "killed by signal 11
  // (SEGV) <when>", "exited (status 0) <when>".
  std::string ended_reason(const std::string& when) {
    ProcessOutcome o;
    wait_for_plugin_exit(pid_, 100.0);  // an end on its way (stdout closes just before it)
    stop(/*graceful=*/false, &o);
    if (o.timed_out) return "closed its stdout " + when;
    const std::string failure = process_failure(o, manifest_.timeout_s);
    return (failure.empty() ? std::string("exited (status 0)") : failure) + " " + when;
  }

  bool send_line(const std::string& line) {
    size_t sent = 0;
    while (sent < line.size()) {
      const ssize_t n = send(socket_, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      sent += static_cast<size_t>(n);
    }
    return true;
  }

  // Whatever is readable now, appended to buffer_; false at end of file.
  bool read_available() {
    char chunk[4096];
    for (;;) {
      const ssize_t n = recv(socket_, chunk, sizeof(chunk), MSG_DONTWAIT);
      if (n > 0) {
        buffer_.append(chunk, static_cast<size_t>(n));
        if (buffer_.size() > kMaxAnswerBytes + 1) return true;  // bounded: judged by the caller
        continue;
      }
      if (n == 0) return false;
      if (errno == EINTR) continue;
      return true;  // EAGAIN: nothing more now
    }
  }

  // What the program wrote before this frame's request (nothing, if it keeps to the protocol).
  std::string drain() {
    read_available();
    std::string s = buffer_;
    buffer_.clear();
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    return s;
  }

  // Frame k's answer line into `line`; "" or why there is none.
  std::string read_line(int k, std::string& line) {
    const std::string frame = "frame " + std::to_string(k);
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
      // Whether it ended, asked before reading: all it wrote before its end is then read below.
      const bool ended = exited();
      const bool open = read_available();
      const size_t newline = buffer_.find('\n');
      if (newline != std::string::npos && newline <= kMaxAnswerBytes) {
        line = buffer_.substr(0, newline);
        buffer_.erase(0, newline + 1);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return "";
      }
      if (buffer_.size() > kMaxAnswerBytes)
        return "answered " + frame + " with a line longer than " +
               std::to_string(kMaxAnswerBytes / 1024) + " KiB: " + quote_line(buffer_);
      if (!open || ended) return ended_reason("before answering " + frame);
      const double left = manifest_.timeout_s * 1000.0 - ms_since(t0);
      if (left <= 0.0)
        return "timed out after " + format_param_value(manifest_.timeout_s) + " s on " + frame +
               " (process group killed)";
      // The socket, and the process's end (pidfd; without one, every 10 ms): a program that
      // dies while a background child holds its stdout open ends the wait too.
      pollfd fds[2] = {{socket_, POLLIN, 0}, {pidfd_, POLLIN, 0}};
      const double slice = pidfd_ >= 0 ? left : std::min(left, 10.0);
      poll(fds, pidfd_ >= 0 ? 2 : 1, static_cast<int>(std::ceil(std::min(slice, 1e9))));
    }
  }

  static std::string check_answer(int k, const std::string& line) {
    const std::string frame = "frame " + std::to_string(k);
    const std::string expected = "{\"frame\": " + std::to_string(k) + ", \"ok\": true}";
    // A JSON line holds no control bytes (JSON escapes them inside strings): NULs after an
    // answer were ignored by the parser, so a damaged answer passed as a good one.
    for (const char c : line)
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t')
        return "answered " + frame + " with " + quote_line(line) +
               ", which holds a control byte (" +
               (c == '\0' ? "NUL" : "code " + std::to_string(c)) + "), not a JSON line " + expected;
    nlohmann::json a;
    try {
      a = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception&) {
      return "answered " + frame + " with " + quote_line(line) + ", not a JSON line " + expected;
    }
    if (!a.is_object() || !a.contains("frame") || !a["frame"].is_number_integer())
      return "answered " + frame + " with " + quote_line(line) + ", not " + expected;
    if (a["frame"].get<int64_t>() != k)
      return "answered frame " + std::to_string(a["frame"].get<int64_t>()) + " to " + frame;
    if (a.contains("error")) {
      // Not a string ({"x": 1}, a number): its JSON text, so the reason is never empty.
      const std::string why =
          a["error"].is_string() ? a["error"].get<std::string>() : a["error"].dump();
      return "reported an error on " + frame + ": " + quote_line(why);
    }
    if (!a.contains("ok") || a["ok"] != true)
      return "answered " + frame + " with " + quote_line(line) + ", not " + expected;
    return "";
  }

  PluginManifest manifest_;
  ParamSet params_;
  PluginFolder folder_;
  const GBuffer* prepared_for_ = nullptr;
  int prepared_frame_ = -1;
  pid_t pid_ = -1;
  int socket_ = -1, pidfd_ = -1;
  std::string start_error_;
  std::string buffer_;  // bytes read past the last answer's newline
};

}  // namespace

std::string process_protocol_text() {
  return "Process plug-in protocols (CONTRACT §7, §10; the manifest's \"protocol\").\n"
         "\"run\" (the default): COMMAND --gbuffer G.exr --params P.json --out AO.exr --frames N\n"
         "is started once per frame (and once per timed repetition), in the plug-in folder, stdin\n"
         "/dev/null. It writes AO.exr (channel AO in [0, 1], the G-buffer's size, optional\n"
         "bent.X/Y/Z) and optionally AO.exr.timing.json {\"frame_ms\": [...], \"passes_ms\":\n"
         "{\"name\": [...]}} timing its N frames; exit status 0.\n"
         "\"frames\": COMMAND (nothing added) is started once per sequence point or still view "
         "and\n"
         "reads one JSON line per frame on stdin (with timing warmup > 0 it is first started once\n"
         "more for the warm-up: frame 0 alone, warmup times, then EOF),\n"
         "  {\"frame\": K, \"gbuffer\": \"/abs/G.exr\", \"params\": \"/abs/P.json\", \"out\": "
         "\"/abs/AO.exr\"}\n"
         "and answers each with one line on stdout, flushed, after writing AO.exr (and optionally\n"
         "AO.exr.timing.json for that frame): {\"frame\": K, \"ok\": true}, or {\"frame\": K,\n"
         "\"error\": \"why\"}. stdout carries only the answers (diagnostics go to stderr). EOF on\n"
         "stdin means exit; " +
         format_param_value(kFramesExitGraceS) +
         " s later its process group is killed. Each answer is waited for at most\n"
         "timeout_s (the first one includes the program's start-up). Any failure (no answer in\n"
         "time, its end before answering, a line that is not that JSON, another frame number, an\n"
         "error it reports, output between frames, a bad AO.exr) skips the row, quoting its last\n"
         "stderr line, and ends the program.\n"
         "Both: G.exr holds CONTRACT §4's channels and, on sequence frames, motion.X, motion.Y "
         "and\n"
         "disoccluded; P.json every parameter, the seed rule applied (seed + k on frame k).\n"
         "Without a timing file a frame's time is the whole process (\"run\", start-up included)\n"
         "or the request's round trip (\"frames\").\n";
}

std::unique_ptr<Estimator> make_frames_process_estimator(const PluginManifest& m,
                                                         const ParamSet& params) {
  return std::make_unique<FramesProcessEstimator>(m, params);
}

}  // namespace aoeval
