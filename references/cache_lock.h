// Many writers on one reference cache (issue 19, CONTRACT §9): shards on several nodes share the
// cache folder (AOEVAL_CACHE on a shared file system) and often need the same reference. Entries
// are written atomically (temporary + rename, exr_io.h), so a reader never sees half a file; this
// lock makes the second process that needs an entry wait for the first instead of computing it
// again. flock(2) on "<entry>.lock": NFSv4 and Lustre map it to byte-range locks, and the kernel
// drops it when its holder dies, so a killed shard never leaves a stuck lock behind.
#pragma once

#include <functional>
#include <string>

namespace aoeval {

class CacheEntryLock {
 public:
  // Blocks until this process holds the exclusive lock of `entry_path` (creating the folder and
  // the lock file as needed). Throws std::runtime_error naming the lock file when it cannot be
  // opened.
  explicit CacheEntryLock(const std::string& entry_path);
  ~CacheEntryLock();
  CacheEntryLock(const CacheEntryLock&) = delete;
  CacheEntryLock& operator=(const CacheEntryLock&) = delete;

 private:
  int fd_ = -1;
};

// The cache's whole protocol in one place: `usable()` is checked without the lock (the common
// hit); on a miss, the lock is taken and `usable()` checked again (another process may have just
// written it); only then is `produce()` called, under the lock, and it must write the entry
// atomically (text_files.h); the temporaries of killed earlier writers are removed before. Returns
// true when this call produced the entry.
bool fill_cache_entry_once(const std::string& entry_path, const std::function<bool()>& usable,
                           const std::function<void()>& produce);

}  // namespace aoeval
