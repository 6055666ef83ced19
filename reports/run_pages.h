// The pages of one output folder, written the same way for `aoeval run`, `sweep` and `merge`:
// from what the folder's store holds, through the one run reader
// (harness/results/suite_record_io.h read_stored_run), never from a runner's memory.
#pragma once

#include <string>

namespace aoeval {

// The G-buffer gallery (<dir>/gbuffers/index.html, when the run rendered scene views) and the
// report (<dir>/index.html, suite_report.h); returns the report's path. A PageWriter.
std::string write_run_pages(const std::string& dir, const std::string& database);

}  // namespace aoeval
