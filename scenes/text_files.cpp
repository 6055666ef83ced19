// Atomic text writes (see text_files.h).
#include "text_files.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace aoeval {

namespace fs = std::filesystem;

std::string temporary_path_for(const std::string& path) {
  static std::atomic<int> counter{0};
  fs::path p(path);
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
  return (dir / name).string();
}

void commit_temporary(const std::string& temporary, const std::string& path) {
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw std::runtime_error("cannot move " + temporary + " to " + path);
  }
}

void write_text(const std::string& path, const std::string& content) {
  const std::string tmp = temporary_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << content;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + path);
    }
  }
  commit_temporary(tmp, path);
}

}  // namespace aoeval
