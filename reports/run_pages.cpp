#include "reports/run_pages.h"

#include <filesystem>

#include "harness/results/suite_record_io.h"
#include "reports/gbuffer_gallery.h"
#include "reports/suite_report.h"

namespace aoeval {

std::string write_run_pages(const std::string& dir, const std::string& database) {
  StoredRun run = read_stored_run(dir, database);
  if (!run.gallery.empty()) {
    write_gbuffer_gallery((std::filesystem::path(dir) / "gbuffers").string(), run.report.suite,
                          run.gallery);
    run.report.gbuffer_gallery = "gbuffers/index.html";
  }
  return write_suite_report(dir, run.report);
}

}  // namespace aoeval
