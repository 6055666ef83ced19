// The run bookkeeping of every runner (run_recorder.h).
#include "harness/results/run_recorder.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <set>

namespace aoeval {

namespace {

// check_output_folder() before the store creates anything; returns `database` for its initialiser.
const std::string& after_checking(const std::string& out_dir, const std::string& database) {
  check_output_folder(out_dir);
  return database;
}

}  // namespace

RunRecorder::RunRecorder(const std::string& out_dir, const std::string& database,
                         const std::string& command, FolderAccess access)
    : out_dir_(out_dir),
      store_(after_checking(out_dir, database)),
      context_(make_run_context(command)),
      folder_(out_dir, context_, "results",
              access == FolderAccess::exclusive ? FolderWrites::append : FolderWrites::whole) {
  if (access == FolderAccess::exclusive) {
    lock_.emplace(out_dir);
    remove_stale_temporaries(out_dir);
  }
}

void RunRecorder::resume() {
  folder_.load_existing();
  if (const auto& existing = folder_.existing_context()) {
    context_.run_id = existing->run_id;
    context_.started = existing->started;
  }
  folder_.set_context(context_);
  std::set<std::string> in_database;
  for (const ResultRow& r : store_.rows_of_run(context_.run_id)) {
    in_database.insert(r.run_name);
    folder_.merge(r);  // committed to SQLite, killed before the files were rewritten
  }
  // What the folder now holds beyond SQLite can only have come from the files.
  for (const ResultRow& r : folder_.rows())
    if (!in_database.count(r.run_name)) store_.add(r);
}

void RunRecorder::write_files() {
  folder_.set_context(context_);
  folder_.write();
}

void RunRecorder::register_run() {
  store_.add_run(context_);
}

ResultRow RunRecorder::stamped(ResultRow row) const {
  row.run_id = context_.run_id;
  row.machine = context_.machine;
  if (row.device.empty()) row.device = context_.device;
  row.git_commit = context_.git_commit;
  return row;
}

ResultRow RunRecorder::record(ResultRow row, StageTimes* stages) {
  PointRecord point;
  point.row = std::move(row);
  return record(std::move(point), stages);
}

namespace {

// The row's estimate_file among the images as role "estimate" when the record does not name it.
PointRecord with_estimate_image(PointRecord record) {
  if (!record.row.estimate_file.empty() &&
      std::none_of(record.images.begin(), record.images.end(),
                   [](const KeptImage& i) { return i.role == "estimate"; }))
    record.images.insert(record.images.begin(), KeptImage{"estimate", record.row.estimate_file});
  return record;
}

}  // namespace

ResultRow RunRecorder::record(PointRecord record, StageTimes* stages) {
  record.row = stamped(std::move(record.row));
  record = with_estimate_image(std::move(record));
  const ResultRow& row = record.row;
  {
    std::optional<StageTimes::Scope> timer;
    if (stages) timer.emplace(*stages, "results SQLite");
    store_.add(record);
  }
  {
    std::optional<StageTimes::Scope> timer;
    if (stages) timer.emplace(*stages, "results CSV + JSON");
    folder_.set_context(context_);
    folder_.add(row);
  }
  return row;
}

void RunRecorder::import_rows(const std::vector<ResultRow>& rows) {
  std::vector<PointRecord> records;
  for (const ResultRow& r : rows) records.push_back({.row = r, .frames = {}, .images = {}});
  import_records(records);
}

void RunRecorder::import_records(const std::vector<PointRecord>& records) {
  for (const PointRecord& r : records) folder_.merge(r.row);
  write_files();
  register_run();
  for (const PointRecord& r : records) store_.add(with_estimate_image(r));
}

// ---------------------------------------------------------------- SIGINT

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_sigint(int) {
  g_interrupted = true;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

InterruptScope::InterruptScope() {
  g_interrupted = false;
  previous_ = std::signal(SIGINT, on_sigint);
}

InterruptScope::~InterruptScope() {
  std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
}

bool InterruptScope::interrupted() const {
  return g_interrupted;
}

bool interrupt_requested() {
  return g_interrupted;
}

}  // namespace aoeval
