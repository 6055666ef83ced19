// Tests of the run recorder (run_recorder.h): rows stamped with the run context, one recorder per
// locked folder, stale temporaries removed, a resumed run keeping its run id without duplicating
// a row, and the SIGINT scope.
#include "harness/results/run_recorder.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = aoeval::testutil::test_temp_dir("recorder") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

ResultRow row_named(const std::string& name, double rmse = 0.1) {
  ResultRow r;
  r.run_name = name;
  r.estimator = "hbao";
  r.params = {{"R", 0.5}};
  r.scene = "bunny";
  r.view = "main";
  r.width = 32;
  r.height = 24;
  r.metrics = {{"rmse", rmse}};
  r.backend = "cpu";
  return r;
}

std::vector<std::string> names(const std::vector<ResultRow>& rows) {
  std::vector<std::string> out;
  for (const ResultRow& r : rows) out.push_back(r.run_name);
  return out;
}

TEST(RunRecorderTest, RowsAreStampedWithTheContext) {
  const fs::path dir = fresh_dir("stamped");
  const std::string db = (dir / "results.sqlite").string();
  RunRecorder recorder((dir / "out").string(), db, "sweep stamped", FolderAccess::exclusive);
  const RunContext& c = recorder.context();
  EXPECT_EQ(c.command, "sweep stamped");
  recorder.write_files();
  recorder.register_run();

  ResultRow cpu = row_named("a");
  cpu.run_id = "someone else's";
  cpu.machine = "elsewhere";
  ResultRow gpu = row_named("b");
  gpu.device = "a GPU";  // a row that names its device keeps it
  const ResultRow a = recorder.record(cpu);
  const ResultRow b = recorder.record(gpu);
  for (const ResultRow* r : {&a, &b}) {
    EXPECT_EQ(r->run_id, c.run_id);
    EXPECT_EQ(r->machine, c.machine);
    EXPECT_EQ(r->git_commit, c.git_commit);
  }
  EXPECT_EQ(a.device, c.device);
  EXPECT_EQ(b.device, "a GPU");

  // The files (results.json once the runner ends) and the store hold the stamped rows, and the
  // store knows the run.
  recorder.write_files();
  std::optional<RunContext> on_disk;
  const std::vector<ResultRow> files =
      read_results_file((dir / "out" / "results.json").string(), &on_disk);
  ASSERT_EQ(names(files), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(files[0].run_id, c.run_id);
  EXPECT_EQ(files[0].device, c.device);
  ASSERT_TRUE(on_disk.has_value());
  EXPECT_EQ(on_disk->run_id, c.run_id);
  SqliteStore store(db);
  const std::vector<ResultRow> stored = store.rows_of_run(c.run_id);
  ASSERT_EQ(names(stored), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(stored[1].device, "a GPU");
  EXPECT_EQ(store.run_ids(), std::vector<std::string>{c.run_id});
}

TEST(RunRecorderTest, RecordTimesItsWritesWhenAsked) {
  const fs::path dir = fresh_dir("timed");
  RunRecorder recorder((dir / "out").string(), (dir / "results.sqlite").string(), "run timed",
                       FolderAccess::exclusive);
  recorder.register_run();
  StageTimes stages;
  recorder.record(row_named("a"), &stages);
  const nlohmann::json j = stages.to_json();
  EXPECT_TRUE(j.contains("results SQLite"));
  EXPECT_TRUE(j.contains("results CSV + JSON"));
}

TEST(RunRecorderTest, ASecondRecorderOnALockedFolderFails) {
  const fs::path dir = fresh_dir("locked");
  const std::string out = (dir / "out").string(), db = (dir / "results.sqlite").string();
  RunRecorder first(out, db, "sweep first", FolderAccess::exclusive);
  try {
    RunRecorder second(out, db, "sweep second", FolderAccess::exclusive);
    FAIL() << "a second recorder took a locked folder";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(out), std::string::npos) << what;
    EXPECT_NE(what.find("another aoeval process"), std::string::npos) << what;
    EXPECT_NE(what.find("pid " + std::to_string(::getpid())), std::string::npos) << what;
  }
  // bench's recorder takes no lock.
  EXPECT_NO_THROW(RunRecorder(out, db, "bench", FolderAccess::shared));
}

TEST(RunRecorderTest, ABadOutputFolderFailsBeforeTheDatabaseIsCreated) {
  const fs::path dir = fresh_dir("bad_out");
  std::ofstream(dir / "a_file") << "x";
  const fs::path db = dir / "results.sqlite";
  EXPECT_THROW(RunRecorder((dir / "a_file" / "out").string(), db.string(), "sweep bad",
                           FolderAccess::exclusive),
               InputError);
  EXPECT_FALSE(fs::exists(db));
}

TEST(RunRecorderTest, StaleTemporariesAreRemovedFromAnExclusiveFolder) {
  const fs::path dir = fresh_dir("stale");
  const fs::path out = dir / "out";
  fs::create_directories(out / "estimates");
  // The plot log a killed plot process left beside its image (empty; drawing/plot.cpp) too: a
  // resumed run must not keep it.
  fs::create_directories(out / "sequences" / "p");
  const std::vector<fs::path> stale = {
      out / ".results.tmp-999999-0.json", out / "estimates" / ".p.tmp-999999-3.exr",
      out / "sequences" / "p" / "rmse_excess.png.plot.log",
      out / "sequences" / "p" / ".rmse_excess.png.plot.tmp-9-0.log"};
  const fs::path kept = out / "results.json.bak";
  for (const fs::path& p : stale) std::ofstream(p) << "partial";
  std::ofstream(kept) << "not a temporary";

  { RunRecorder shared(out.string(), (dir / "db.sqlite").string(), "bench", FolderAccess::shared); }
  for (const fs::path& p : stale) EXPECT_TRUE(fs::exists(p)) << p;  // bench removes nothing

  RunRecorder recorder(out.string(), (dir / "db.sqlite").string(), "sweep stale",
                       FolderAccess::exclusive);
  for (const fs::path& p : stale) EXPECT_FALSE(fs::exists(p)) << p;
  EXPECT_TRUE(fs::exists(kept));
}

TEST(RunRecorderTest, AResumedRunKeepsItsRunIdAndDuplicatesNoRow) {
  const fs::path dir = fresh_dir("resume");
  const std::string out = (dir / "out").string(), db = (dir / "results.sqlite").string();
  std::string run_id, started;
  {
    RunRecorder first(out, db, "sweep resumed", FolderAccess::exclusive);
    first.resume();  // nothing to resume: the fresh context stays
    first.write_files();
    first.register_run();
    run_id = first.context().run_id;
    started = first.context().started;
    first.record(row_named("a"));
    first.record(row_named("b"));
    // Killed between the SQLite commit of "c" and the rewrite of the files: "c" is in SQLite only.
    SqliteStore(db).add(first.stamped(row_named("c")));
  }
  {
    // A row in the files only (a history lost, or a resume given another --db): "d".
    ResultsFolder folder(out, RunContext{});
    folder.load_existing();
    folder.set_context(*folder.existing_context());
    ResultRow d = row_named("d");
    d.run_id = run_id;
    folder.add(d);
  }

  RunRecorder again(out, db, "sweep resumed", FolderAccess::exclusive);
  EXPECT_NE(make_run_context("sweep resumed").run_id, run_id);
  again.resume();
  EXPECT_EQ(again.context().run_id, run_id);
  EXPECT_EQ(again.context().started, started);
  again.write_files();
  again.register_run();
  EXPECT_EQ(names(again.rows()), (std::vector<std::string>{"a", "b", "d", "c"}));
  // The point in progress when it was killed runs again: its row replaces, never duplicates.
  again.record(row_named("b", 0.2));
  again.record(row_named("e"));

  again.write_files();
  const std::vector<ResultRow> files = read_results_file((fs::path(out) / "results.json").string());
  EXPECT_EQ(names(files), (std::vector<std::string>{"a", "b", "d", "c", "e"}));
  EXPECT_EQ(files[1].metrics["rmse"], 0.2);
  SqliteStore store(db);
  EXPECT_EQ(store.run_ids(), std::vector<std::string>{run_id});  // one run, however interrupted
  std::multiset<std::string> stored;
  for (const ResultRow& r : store.rows_of_run(run_id)) stored.insert(r.run_name);
  EXPECT_EQ(stored, (std::multiset<std::string>{"a", "b", "c", "d", "e"}));
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// An exclusive folder appends each row (O(1) a row): results.json is not rewritten until the
// runner's write_files(), the CSV appended is the CSV a whole write gives (also when a row brings
// a column or replaces a row), and a run killed between two write_files() loses no row: the
// journal gives them back, even without SQLite (another --db), a last line cut short left out.
TEST(RunRecorderTest, AppendedRowsAreKeptByTheJournalThroughAKill) {
  const fs::path dir = fresh_dir("journal");
  const fs::path out = dir / "out";
  const fs::path json = out / "results.json", csv = out / "results.csv",
                 journal = out / "results.rows.jsonl";
  std::string run_id;
  {
    RunRecorder first(out.string(), (dir / "a.sqlite").string(), "sweep j",
                      FolderAccess::exclusive);
    first.write_files();
    run_id = first.context().run_id;
    const std::string written = read_all(json);
    for (const char* n : {"a", "b", "c"}) first.record(row_named(n));
    EXPECT_EQ(read_all(json), written) << "results.json rewritten by a row";
    EXPECT_EQ(read_all(csv), results_csv(first.rows()));
    ResultRow wide = row_named("d");
    wide.params["Nd"] = 8;  // a new column: the header changes
    first.record(wide);
    EXPECT_EQ(read_all(csv), results_csv(first.rows()));
    first.record(row_named("b", 0.3));  // replaced in place
    EXPECT_EQ(read_all(csv), results_csv(first.rows()));
    first.record(row_named("e"));
    EXPECT_EQ(read_all(csv), results_csv(first.rows()));
    EXPECT_EQ(read_all(json), written);
  }
  std::ofstream(journal, std::ios::app) << "{\"run_name\": \"f\", \"est";  // a kill mid-append

  RunRecorder again(out.string(), (dir / "b.sqlite").string(), "sweep j", FolderAccess::exclusive);
  again.resume();
  EXPECT_EQ(again.context().run_id, run_id);
  EXPECT_EQ(names(again.rows()), (std::vector<std::string>{"a", "b", "c", "d", "e"}));
  again.write_files();
  EXPECT_FALSE(fs::exists(journal));
  const std::vector<ResultRow> files = read_results_file(json.string());
  EXPECT_EQ(names(files), (std::vector<std::string>{"a", "b", "c", "d", "e"}));
  EXPECT_EQ(files[1].metrics["rmse"], 0.3);
  EXPECT_EQ(read_all(csv), results_csv(files));
  // The second database got the rows only the files held.
  EXPECT_EQ(SqliteStore((dir / "b.sqlite").string()).rows_of_run(run_id).size(), 5u);

  // A damaged line that is not the last is bad input, named by file and line.
  again.record(row_named("g"));
  again.record(row_named("h"));
  std::string lines = read_all(journal);
  lines.replace(0, 1, "[");
  std::ofstream(journal, std::ios::trunc) << lines;
  ResultsFolder folder(out.string(), RunContext{});
  try {
    folder.load_existing();
    FAIL() << "a damaged journal line was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(journal.string() + ": line 1"), std::string::npos)
        << e.what();
  }
}

TEST(RunRecorderTest, ImportedRowsKeepTheirIdentity) {
  const fs::path dir = fresh_dir("import");
  const std::string db = (dir / "results.sqlite").string();
  RunRecorder recorder((dir / "out").string(), db, "merge", FolderAccess::exclusive);
  ResultRow a = row_named("a"), b = row_named("b");
  a.run_id = b.run_id = recorder.context().run_id;
  a.machine = "node-1";
  b.machine = "node-2";
  recorder.import_rows({a, b, a});
  const std::vector<ResultRow> files = read_results_file((dir / "out" / "results.json").string());
  ASSERT_EQ(names(files), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(files[0].machine, "node-1");
  EXPECT_EQ(files[1].machine, "node-2");
  EXPECT_EQ(SqliteStore(db).rows_of_run(recorder.context().run_id).size(), 2u);
}

volatile std::sig_atomic_t g_previous_calls = 0;
extern "C" void previous_handler(int) {
  g_previous_calls = g_previous_calls + 1;
}

void (*current_sigint_handler())(int) {
  struct sigaction now {};
  ::sigaction(SIGINT, nullptr, &now);
  return now.sa_handler;
}

TEST(InterruptScopeTest, SigintSetsTheFlagAndThePreviousHandlerComesBack) {
  auto* const before = std::signal(SIGINT, previous_handler);
  {
    InterruptScope scope;
    EXPECT_FALSE(scope.interrupted());
    EXPECT_FALSE(interrupt_requested());
    EXPECT_NE(current_sigint_handler(), previous_handler);
    std::raise(SIGINT);
    EXPECT_TRUE(scope.interrupted());
    EXPECT_TRUE(interrupt_requested());
    EXPECT_EQ(current_sigint_handler(), SIG_DFL);  // a second Ctrl-C would end the process
    EXPECT_EQ(g_previous_calls, 0);
  }
  EXPECT_EQ(current_sigint_handler(), previous_handler);
  EXPECT_TRUE(interrupt_requested());  // still readable after the scope, for the exit status
  std::raise(SIGINT);
  EXPECT_EQ(g_previous_calls, 1);
  {
    InterruptScope next;  // a new scope starts uninterrupted
    EXPECT_FALSE(next.interrupted());
  }
  EXPECT_EQ(current_sigint_handler(), previous_handler);
  std::signal(SIGINT, before == SIG_ERR ? SIG_DFL : before);
}

}  // namespace
}  // namespace aoeval
