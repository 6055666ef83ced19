#include "references/cache_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "base/text_files.h"

namespace aoeval {

CacheEntryLock::CacheEntryLock(const std::string& entry_path) {
  const std::string lock_path = entry_path + ".lock";
  const std::filesystem::path dir = std::filesystem::path(lock_path).parent_path();
  std::error_code ec;
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  // The lock file is never removed: removing it while another process waits on the old inode
  // would let a third process lock a new file and produce the entry concurrently.
  fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0)
    throw std::runtime_error("reference cache: cannot open " + lock_path + ": " +
                             std::strerror(errno));
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw std::runtime_error("reference cache: cannot lock " + lock_path + ": " + why);
  }
}

CacheEntryLock::~CacheEntryLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

bool fill_cache_entry_once(const std::string& entry_path, const std::function<bool()>& usable,
                           const std::function<void()>& produce) {
  if (usable()) return false;
  CacheEntryLock lock(entry_path);
  if (usable()) return false;  // written by another process while this one waited
  // Every writer holds this lock while its temporary exists, so any temporary of the entry here
  // is a killed writer's (on any node sharing the cache): removed, or they would stay for good.
  remove_temporaries_of(entry_path);
  produce();
  return true;
}

}  // namespace aoeval
