// Atomic file writes without images: a temporary file beside the target, then rename, so a failed
// or interrupted command never leaves a partial file. The base of exr_io.h's image writes, and all
// that results/ (rows, stores, writers) needs to write its files.
#pragma once

#include <string>

namespace aoeval {

// Writes a text file atomically.
void write_text(const std::string& path, const std::string& content);

// The temporary path used for an atomic write of `path` (its folder created if missing), and the
// rename that commits it.
std::string temporary_path_for(const std::string& path);
void commit_temporary(const std::string& temporary, const std::string& path);

}  // namespace aoeval
