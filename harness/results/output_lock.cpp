#include "harness/results/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>

#include "base/errors.h"

namespace aoeval {

namespace fs = std::filesystem;

void check_output_folder(const std::string& dir, const std::string& option) {
  fs::path p = fs::absolute(dir.empty() ? "." : dir).lexically_normal();
  std::error_code ec;
  while (!fs::exists(p, ec) && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  if (!fs::is_directory(p, ec))
    throw InputError(option + " " + dir + ": " + p.string() + " is a file, not a folder");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError(option + " " + dir + ": cannot write into " + p.string() + ": " +
                     std::strerror(errno));
}

OutputFolderLock::OutputFolderLock(const std::string& dir) {
  fs::create_directories(dir.empty() ? "." : dir);
  const std::string path = (fs::path(dir.empty() ? "." : dir) / ".aoeval.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(dir + ": cannot create " + path + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    std::ifstream in(path);
    std::string holder;
    std::getline(in, holder);
    ::close(fd_);
    fd_ = -1;
    throw InputError(dir + ": another aoeval process" +
                     (holder.empty() ? std::string() : " (pid " + holder + ")") +
                     " is writing results into this folder; give each process its own --out");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is only for the message above; the lock itself is what matters.
  }
}

OutputFolderLock::~OutputFolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

size_t remove_stale_temporaries(const std::string& dir) {
  // Temporaries, and the <image>.plot.log that a plot process killed with its run left beside
  // the image before the log became a temporary itself (drawing/plot.cpp).
  static const std::regex temporary(R"(\..+\.tmp-[0-9]+-[0-9]+(\.[A-Za-z0-9]+)?|.+\.plot\.log)");
  size_t removed = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    if (std::regex_match(it->path().filename().string(), temporary) && fs::remove(it->path(), ec))
      ++removed;
  }
  return removed;
}

}  // namespace aoeval
