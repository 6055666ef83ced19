// What `aoeval run` keeps of its report besides the rows (suite_record.h), on disk as
// <out>/suite_record.json, so that `aoeval merge` can write the report of a suite run in shards
// (issue 19, CONTRACT §9) exactly as one machine would: which rows are featured, where each row's
// mosaic and references are, and the G-buffer gallery's scene views. The rows themselves stay in
// results.json; entries are keyed by run name.
#pragma once

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
// The report of one output folder: its rows and context (results.json) joined with its record
// (a sweep's page, written after the sweep from what it stored).
SuiteReport read_suite_report(const std::string& dir);

}  // namespace aoeval
