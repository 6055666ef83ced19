// What `aoeval run` keeps of its report besides the rows (suite_record.h), on disk as
// <out>/suite_record.json, so that `aoeval merge` can write the report of a suite run in shards
// (issue 19, CONTRACT §9) exactly as one machine would: which rows are featured, where each row's
// mosaic and references are, and the G-buffer gallery's scene views. The rows themselves stay in
// results.json, their kept files in the SQLite store; entries are keyed by run name.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "harness/results/suite_record.h"

namespace aoeval {

struct SuiteRecordFile {
  std::string suite, suite_file;
  std::vector<std::string> overrides;
  double wall_s = 0.0;
  std::map<std::string, SuiteReportEntry> entries;  // by run name; entry.row is left empty
  std::vector<GalleryEntry> gallery;
};

// Writes <out_dir>/suite_record.json (atomically) from a report and its gallery.
void write_suite_record(const std::string& out_dir, const SuiteReport& report,
                        const std::vector<GalleryEntry>& gallery);
// True when <dir>/suite_record.json exists.
bool has_suite_record(const std::string& dir);
// InputError naming the file and field when it is unreadable or not a record.
SuiteRecordFile read_suite_record(const std::string& dir);
// The run reader: what the pages of one output folder show, from what its store holds. The rows
// and context from <dir>/results.json, the suite, featured rows and G-buffer views from
// <dir>/suite_record.json, and each row's kept files by role (entry.images; the mosaic and
// references taken from them) from the SQLite store `database` (read only: the images table of
// the row's run). `aoeval run`, `sweep` and `merge` write their pages from it alone
// (reports/run_pages.h). InputError naming the file when one is unreadable.
struct StoredRun {
  SuiteReport report;
  std::vector<GalleryEntry> gallery;
};
StoredRun read_stored_run(const std::string& dir, const std::string& database);

// Writes the pages of output folder `dir` from read_stored_run(dir, database) and returns the main
// page's path (reports/run_pages.h, handed to a runner by cmd/, so that no runner links reports/).
// A runner calls it after its last write of rows and record, while it still holds the folder's
// lock: the lock stays with the runner for the whole write.
using PageWriter = std::function<std::string(const std::string& dir, const std::string& database)>;

}  // namespace aoeval
