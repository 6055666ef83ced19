// One writer per output folder. A sweep or suite rewrites its folder's results files whole after
// every row; two processes given the same --out would each overwrite the other's rows (last writer
// wins, half the rows gone, both exit 0). The lock turns that into an immediate, named error.
#pragma once

#include <string>

namespace aoeval {

// Validates an output folder before anything is created (so a bad --out leaves no empty database
// or folder behind): InputError naming `option` and the path when it, or the nearest existing
// folder above it, is a file, or when that folder cannot be written into. Creates nothing.
void check_output_folder(const std::string& dir, const std::string& option = "--out");

class OutputFolderLock {
 public:
  // Creates `dir` and takes an exclusive flock on <dir>/.aoeval.lock (released by the kernel when
  // the process ends, however it ends: a SIGKILLed sweep never leaves a stale lock). Throws
  // InputError naming the folder and the holder's pid when another process holds it.
  explicit OutputFolderLock(const std::string& dir);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

 private:
  int fd_ = -1;
};

// Removes the temporary files of interrupted atomic writes (".<stem>.tmp-<pid>-<n><ext>", see
// temporary_path_for) anywhere under `dir`, and any "<image>.plot.log" (a killed plot process's log
// from before it was a temporary). Call it while holding the folder's lock: no other
// aoeval process writes there then, so every such file is left over from a killed one. Returns how
// many were removed.
size_t remove_stale_temporaries(const std::string& dir);

}  // namespace aoeval
