#include "drawing/plot_workers.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <stdexcept>

#include "drawing/plot.h"

namespace aoeval {

struct PlotWorkers::Worker {
  pid_t pid = -1;
  int socket = -1;                // both directions: jobs out, answers in
  bool busy = false;              // guarded by the pool's mutex
  std::atomic<bool> dead{false};  // also set by draw(), which runs without the mutex
  std::string pending;            // bytes read past the last answer's newline
};

namespace {

// A socket, not pipes: a write to a worker that died must fail with EPIPE (send with
// MSG_NOSIGNAL), not kill aoeval with SIGPIPE.
std::unique_ptr<PlotWorkers::Worker> spawn() {
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) return nullptr;
  std::string python = plot_python(), script = plot_script(), serve = "--serve";
  char* argv[] = {python.data(), script.data(), serve.data(), nullptr};
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    close(ends[0]);
    close(ends[1]);
    return nullptr;
  }
  if (pid == 0) {  // only async-signal-safe calls until exec
    // Stopped workers of a killed aoeval would wait forever: they die with it.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1);
    dup2(ends[1], STDIN_FILENO);
    dup2(ends[1], STDOUT_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDERR_FILENO);
    execvp(argv[0], argv);
    _exit(127);
  }
  close(ends[1]);
  auto worker = std::make_unique<PlotWorkers::Worker>();
  worker->pid = pid;
  worker->socket = ends[0];
  return worker;
}

bool send_all(int socket, const std::string& bytes) {
  size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = send(socket, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    sent += static_cast<size_t>(n);
  }
  return true;
}

// One answer line without its newline, or false at end of stream.
bool read_line(PlotWorkers::Worker& w, std::string& line) {
  for (;;) {
    const size_t end = w.pending.find('\n');
    if (end != std::string::npos) {
      line = w.pending.substr(0, end);
      w.pending.erase(0, end + 1);
      return true;
    }
    char buffer[4096];
    const ssize_t n = read(w.socket, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    w.pending.append(buffer, static_cast<size_t>(n));
  }
}

// Idle workers hold no job, so killing them loses nothing (one still importing matplotlib would
// otherwise hold the exit for half a second).
void reap(PlotWorkers::Worker& w) {
  if (w.socket >= 0) close(w.socket);
  w.socket = -1;
  if (w.pid > 0) {
    kill(w.pid, SIGKILL);
    int status = 0;
    while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  w.pid = -1;
  w.dead = true;
}

}  // namespace

PlotWorkers& PlotWorkers::instance() {
  static PlotWorkers pool;
  return pool;
}

PlotWorkers::~PlotWorkers() {
  stop();
}

void PlotWorkers::start(int count) {
  std::lock_guard lock(mutex_);
  int alive = 0;
  for (const auto& w : workers_) alive += !w->dead;
  for (; alive < count; ++alive) {
    auto w = spawn();
    if (!w) return;
    if (frozen_) kill(w->pid, SIGSTOP);
    workers_.push_back(std::move(w));
  }
}

void PlotWorkers::freeze() {
  std::lock_guard lock(mutex_);
  frozen_ = true;
  for (const auto& w : workers_)
    if (!w->dead) kill(w->pid, SIGSTOP);
}

void PlotWorkers::thaw() {
  std::lock_guard lock(mutex_);
  frozen_ = false;
  for (const auto& w : workers_)
    if (!w->dead) kill(w->pid, SIGCONT);
}

void PlotWorkers::stop() {
  std::lock_guard lock(mutex_);
  frozen_ = false;
  for (const auto& w : workers_)
    if (!w->dead) reap(*w);
  workers_.clear();
}

std::vector<pid_t> PlotWorkers::pids() {
  std::lock_guard lock(mutex_);
  std::vector<pid_t> alive;
  for (const auto& w : workers_)
    if (!w->dead) alive.push_back(w->pid);
  return alive;
}

PlotWorkers::Worker* PlotWorkers::acquire() {
  std::lock_guard lock(mutex_);
  if (frozen_) return nullptr;
  for (const auto& w : workers_)
    if (!w->dead && !w->busy) {
      w->busy = true;
      return w.get();
    }
  return nullptr;
}

void PlotWorkers::release(Worker* worker) {
  std::lock_guard lock(mutex_);
  worker->busy = false;
  if (worker->dead) reap(*worker);
}

bool PlotWorkers::draw(Worker& w, const std::string& spec_path, const std::string& out_path) {
  if (spec_path.find_first_of("\t\n") != std::string::npos ||
      out_path.find_first_of("\t\n") != std::string::npos)
    return false;  // not expressible in the line protocol: a process of its own draws it
  std::string answer;
  if (!send_all(w.socket, spec_path + "\t" + out_path + "\n") || !read_line(w, answer)) {
    w.dead = true;
    return false;
  }
  if (answer == "ok") return true;
  throw std::runtime_error(
      "plot " + out_path + ": " + plot_python() + " " + plot_script() +
      " failed: " + (answer.rfind("error: ", 0) == 0 ? answer.substr(7) : answer));
}

}  // namespace aoeval
