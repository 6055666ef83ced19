// Atomic text writes and their temporaries (see text_files.h).
#include "base/text_files.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "base/errors.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// The open temporaries, readable from a signal handler: fixed slots whose state is a lock-free
// atomic (0 free, 1 being filled or emptied, 2 holds a path). A temporary that finds no free slot
// (more than kSlots writes at once) is simply not removed on an interrupt; the next run's cleanup
// takes it.
constexpr int kSlots = 64;
struct Slot {
  std::atomic<int> state{0};
  char path[4096];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free);

void remember(const std::string& temporary) {
  if (temporary.size() >= sizeof(Slot::path)) return;
  for (Slot& s : g_slots) {
    int expected = 0;
    if (!s.state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(s.path, temporary.c_str(), temporary.size() + 1);
    s.state.store(2);
    return;
  }
}

void forget(const std::string& temporary) {
  for (Slot& s : g_slots) {
    if (s.state.load() != 2 || temporary != s.path) continue;
    int expected = 2;
    if (s.state.compare_exchange_strong(expected, 1)) s.state.store(0);
    return;
  }
}

extern "C" void remove_open_temporaries_and_exit(int signal) {
  for (Slot& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.path);  // async-signal-safe, like everything here
  const char message[] = "aoeval: interrupted\n";
  if (::write(STDERR_FILENO, message, sizeof message - 1) < 0) {
    // Nothing to do: the exit status says it.
  }
  ::_exit(128 + signal);
}

// Calls `fn(path, pid)` for each temporary of `target` (".<stem>.tmp-<pid>-<n><ext>").
template <typename Fn>
size_t for_each_temporary_of(const std::string& target, Fn&& fn) {
  const fs::path p(target);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::string prefix(".");
  prefix.append(p.stem().string()).append(".tmp-");
  const std::string ext = p.extension().string();
  size_t removed = 0;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() + ext.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - ext.size(), ext.size(), ext) != 0)
      continue;
    const std::string middle =
        name.substr(prefix.size(), name.size() - prefix.size() - ext.size());  // "<pid>-<n>"
    const size_t dash = middle.find('-');
    if (dash == 0 || dash == std::string::npos || dash > 9 || dash + 1 == middle.size() ||
        middle.find_first_not_of("0123456789-") != std::string::npos ||
        middle.find('-', dash + 1) != std::string::npos)
      continue;
    std::error_code remove_ec;
    if (fn(std::stol(middle.substr(0, dash))) && fs::remove(it->path(), remove_ec)) ++removed;
  }
  return removed;
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  static std::atomic<int> counter{0};
  fs::path p(path);
  // A folder cannot be replaced by a file: said here, before a temporary exists, rather than as a
  // failed rename naming the temporary.
  std::error_code ec;
  if (p.filename().empty() || fs::is_directory(p, ec))
    throw InputError(path + ": is a folder; give the path of a file to write");
  fs::path dir = p.parent_path();
  if (!dir.empty() && !fs::exists(dir)) fs::create_directories(dir);
  // Keep the extension last so format detection by name still works on the temporary.
  // Built with append rather than operator+ chains: GCC 12 warns falsely (-Wrestrict, PR 105329)
  // on "." + std::string.
  std::string name(".");
  name.append(p.stem().string())
      .append(".tmp-")
      .append(std::to_string(getpid()))
      .append("-")
      .append(std::to_string(counter++))
      .append(p.extension().string());
  const std::string temporary = (dir / name).string();
  remember(temporary);
  return temporary;
}

void commit_temporary(const std::string& temporary, const std::string& path) {
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    discard_temporary(temporary);
    throw std::runtime_error("cannot move " + temporary + " to " + path);
  }
  forget(temporary);
}

void discard_temporary(const std::string& temporary) {
  std::error_code ec;
  fs::remove(temporary, ec);
  forget(temporary);
}

size_t remove_dead_temporaries_of(const std::string& path) {
  return for_each_temporary_of(path, [](long pid) {
    return pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
  });
}

size_t remove_temporaries_of(const std::string& path) {
  return for_each_temporary_of(path, [](long pid) { return pid != ::getpid(); });
}

void install_interrupt_cleanup() {
  struct sigaction action {};
  action.sa_handler = remove_open_temporaries_and_exit;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM}) ::sigaction(signal, &action, nullptr);
}

void write_text(const std::string& path, const std::string& content) {
  const std::string tmp = temporary_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << content;
    out.flush();
    if (!out) {
      discard_temporary(tmp);
      throw std::runtime_error("cannot write " + path);
    }
  }
  commit_temporary(tmp, path);
}

}  // namespace aoeval
