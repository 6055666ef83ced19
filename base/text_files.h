// Atomic file writes without images: a temporary file beside the target, then rename, so a failed
// or interrupted command never leaves a partial file. The base of exr_io.h's image writes, and all
// that results/ (rows, stores, writers) needs to write its files.
//
// Temporaries are named ".<stem>.tmp-<pid>-<n><ext>" beside their target. What a killed process
// leaves is cleaned by the next one: remove_dead_temporaries_of() (the pid no longer runs here),
// remove_temporaries_of() (under a lock every writer of the target takes), and
// remove_stale_temporaries() (output_lock.h: a whole locked output folder). An interrupted one
// (SIGINT, SIGTERM) cleans its own with install_interrupt_cleanup().
#pragma once

#include <cstddef>
#include <string>

namespace aoeval {

// Writes a text file atomically.
void write_text(const std::string& path, const std::string& content);

// The temporary path used for an atomic write of `path` (its folder created if missing; an
// InputError naming `path` when it is a folder), and the
// rename that commits it. Between the two the temporary is this process's open temporary (see
// install_interrupt_cleanup); discard_temporary() removes one that will not be committed.
std::string temporary_path_for(const std::string& path);
void commit_temporary(const std::string& temporary, const std::string& path);
void discard_temporary(const std::string& temporary);

// Removes the temporaries of `path` whose process is dead on this machine (a pid that does not
// run; a live pid, perhaps another process's after reuse, keeps its file). Returns how many.
size_t remove_dead_temporaries_of(const std::string& path);
// Removes every temporary of `path` whatever its pid: only for callers that hold a lock every
// writer of `path` takes while its temporary exists (the reference cache's entry lock), so every
// such file is a dead writer's, on this machine or another sharing the folder.
size_t remove_temporaries_of(const std::string& path);

// From now on, SIGINT and SIGTERM remove this process's open temporaries, print "aoeval:
// interrupted" on stderr and end it with 128 + the signal (130 for Ctrl-C), as a shell reports
// it. For the commands that compute and then write their outputs (reference, estimate, gbuffer).
void install_interrupt_cleanup();

}  // namespace aoeval
