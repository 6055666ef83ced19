#include "reports/page_assets.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "base/text_files.h"
#include "reports/viewer_assets.h"

namespace aoeval {

namespace fs = std::filesystem;

void write_if_changed(const fs::path& path, const std::string& content) {
  std::error_code ec;
  if (fs::exists(path, ec)) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    if (s.str() == content) return;
  }
  write_text(path.string(), content);
}

void write_page_asset(const std::string& page_dir, const std::string& name) {
  for (const ViewerAsset& a : page_assets())
    if (a.name == name) return write_if_changed(fs::path(page_dir) / name, std::string(a.content));
  throw std::logic_error("page_assets: no built-in page file '" + name + "'");
}

Html page_stylesheet(const std::string& page_dir, const std::string& name) {
  write_page_asset(page_dir, name);
  return Html("<link rel=\"stylesheet\" href=\"") << attr(name) << "\">\n";
}

}  // namespace aoeval
