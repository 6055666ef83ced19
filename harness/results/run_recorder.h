// The run bookkeeping every runner shares (sweep, suite, tune, bench, merge): the output folder
// checked (and, for the runners that rewrite it row by row, locked and cleared of the leftovers of
// killed writes), the SQLite history opened, the run context made or resumed, rows stamped with it
// and stored, and SIGINT turned into a flag that stops a run between two rows.
//
// The order is what makes a run safe to kill at any instant (SIGKILL included) and resume without
// losing or duplicating a row:
//  1. the folder is checked, then the database opened, so a bad --out or an unwritable --db fails
//     before any folder exists;
//  2. the folder is locked, so no second process writes it, and leftovers of killed atomic writes
//     are removed;
//  3. a runner that resumes writes results.json (with the run context, possibly no rows) before
//     any row reaches the database (write_files()), so the run id is on disk before it is used: a
//     resume keeps it, and one run is one run in the history however often it was interrupted;
//  4. each row is committed to SQLite first, then the files derived from it are written: in an
//     exclusive folder appended (results.csv and the journal results.rows.jsonl, O(1) a row;
//     ResultsFolder, FolderWrites::append), results.json being rewritten whole only by
//     write_files() at the runner's start, resume and end; in a shared one rewritten whole. A kill
//     between the two leaves the row in SQLite only; resume() takes it back from there into the
//     files instead of running the point again.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "harness/results/output_lock.h"
#include "harness/results/results_store.h"
#include "harness/results/stage_times.h"

namespace aoeval {

// Whether a run owns its output folder while it records.
enum class FolderAccess {
  // One writer: <out>/.aoeval.lock held for the recorder's life (a second process given the same
  // folder gets an InputError naming the holder), and the temporaries of killed writes removed.
  // The runners that append their rows and may resume: sweep, suite, tune, merge.
  exclusive,
  // No lock, nothing removed, the files rewritten whole after each row: `aoeval bench`, which
  // writes its few timing rows at the end of a measurement and never resumes.
  shared,
};

class RunRecorder {
 public:
  // check_output_folder(out_dir) (nothing created for a bad --out), the SQLite history at
  // `database`, the folder lock and the removal of stale temporaries (FolderAccess::exclusive),
  // and a fresh run context for `command` (make_run_context). Writes no file of the folder: see
  // write_files(), register_run(), record().
  RunRecorder(const std::string& out_dir, const std::string& database, const std::string& command,
              FolderAccess access);
  RunRecorder(const RunRecorder&) = delete;
  RunRecorder& operator=(const RunRecorder&) = delete;

  // The run's context. A runner amends it before the first write: output_dir (how each runner
  // names its folder is its own), stages_ms at the end; every later write carries it.
  RunContext& context() { return context_; }
  const RunContext& context() const { return context_; }
  const std::string& out_dir() const { return out_dir_; }
  // The rows recorded so far (and, after resume(), those of the earlier invocations), in order.
  const std::vector<ResultRow>& rows() const { return folder_.rows(); }

  // Continues the run of <out>/results.json: its rows are loaded (InputError naming the file when
  // it is unreadable), its run_id and started are kept, rows committed to SQLite but not to the
  // files (killed between the two) are taken back into them, and rows in the files but not in
  // SQLite are added to it. No results.json: nothing loaded, the fresh context kept. Writes
  // nothing itself: call write_files() and register_run() after it.
  void resume();
  // Rewrites results.json and results.csv from the rows held and the context (atomically), and
  // removes the journal: every runner calls it when it ends (interrupted or not), so a finished
  // folder's results.json holds every row.
  void write_files();
  // Adds the run (its context) to the history's runs table, replacing an earlier entry of its id.
  void register_run();

  // The row with the run's identity: run_id, machine and git_commit from the context, and the
  // context's device where the row names none (CPU estimators leave it to the runner).
  ResultRow stamped(ResultRow row) const;
  // stamped(row) committed to SQLite, then to the files (appended or rewritten, as FolderAccess
  // says; a row of the same run_name replaced); returns the stamped row. With `stages`, the two
  // writes are timed as "results SQLite" and "results CSV + JSON".
  ResultRow record(ResultRow row, StageTimes* stages = nullptr);
  // The same for a whole point: its row, frames and kept images go to SQLite in one transaction
  // (the row's estimate_file among the images as role "estimate" when the record does not name
  // it), then the row to the files. A sequence point's frames.csv is written by its runner before
  // this call (kept_sequence.h), so a committed row has it.
  ResultRow record(PointRecord record, StageTimes* stages = nullptr);
  // Rows that already carry their identity (merge: each keeps the machine, device and commit of
  // the shard that measured it; the caller sets their run_id): appended to the files as they are,
  // a row whose run_name is already held skipped, the files written once, then the run and every
  // row added to SQLite.
  void import_rows(const std::vector<ResultRow>& rows);
  // The same for whole points (merge: a sequence point's frames and kept images with its row),
  // each committed to SQLite as record() commits one.
  void import_records(const std::vector<PointRecord>& records);

 private:
  std::string out_dir_;
  SqliteStore store_;
  std::optional<OutputFolderLock> lock_;
  RunContext context_;
  ResultsFolder folder_;
};

// While one lives, SIGINT sets a flag instead of ending the process, so that a runner stops
// cleanly between two rows and keeps every row it wrote (then returns exit status 130); a
// second SIGINT ends the process at once. The handler it replaced is restored when it ends.
// Construction clears the flag.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  bool interrupted() const;

 private:
  void (*previous_)(int) = nullptr;
};

// Whether a SIGINT arrived during the latest InterruptScope (still true after it ended, until the
// next one begins). For code that asks from outside the scope's block (a search callback).
bool interrupt_requested();

}  // namespace aoeval
