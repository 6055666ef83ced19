// Where results rows go (CONTRACT §4 "Results"; STYLE "Reporters are separate from runners"):
// the run context, an output folder's results.csv + results.json, the SQLite history database,
// and the text writers (CSV, JSON, Markdown, console). Every writer reads the same ResultRows.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "harness/results/point_record.h"
#include "harness/results/result_row.h"

struct sqlite3;

namespace aoeval {

// What one invocation of sweep/run/bench shares across its rows (the JSON "context" block).
struct RunContext {
  std::string run_id;          // UTC timestamp + random suffix: "20240501T123456Z-3f9a1c"
  std::string command;         // "sweep hbao-radius", "run default", ...
  std::string machine;         // "hostname (CPU model, N cores)"
  std::string device;          // the CPU model; the caller replaces it when a GPU runs
  std::string embree_version;  // RTC_VERSION_STRING, "unknown" where Embree's header is absent
  std::string git_commit;      // `git rev-parse HEAD` of the source tree, or "unknown"
  std::string aoeval_version;
  std::string started;     // ISO 8601 UTC: "2024-05-01T12:34:56Z"
  std::string output_dir;  // absolute path of the output folder (images, EXRs); "" if none
  // Where the run's wall time went, stage -> ms (StageTimes, stage_times.h), plus "wall"; an
  // empty object until the run ends.
  nlohmann::json stages_ms = nlohmann::json::object();
};

RunContext make_run_context(const std::string& command);
nlohmann::json to_json(const RunContext& context);
RunContext run_context_from_json(const nlohmann::json& j);

// The ordered union of the columns of `rows`: identifying_columns(), then parameter columns in
// order of first appearance, then measured_columns(), then pass columns in order of first
// appearance. The header of results.csv and the column set of the SQLite results table.
std::vector<std::string> result_columns(const std::vector<ResultRow>& rows);
// The same union grown one row at a time (a folder that appends rows keeps one, so the header of
// its CSV costs nothing per row): add() returns true when the row brought a column.
class ResultColumns {
 public:
  bool add(const ResultRow& row);
  std::vector<std::string> list() const;

 private:
  std::vector<std::string> params_, passes_;
  std::set<std::string> seen_params_, seen_passes_;
};
// One results.csv line (no newline) of `flat` (flatten(row)) under `columns`, as results_csv
// writes it.
std::string csv_line(const nlohmann::json& flat, const std::vector<std::string>& columns);
// A sequence point's frames.csv (CONTRACT §10): one line per frame, columns frame, time_ms,
// disoccluded_pixels, then the metric keys and true_ metric keys in results order.
std::string frames_csv(const std::vector<nlohmann::json>& frames);
// Where it lives: <out>/sequences/<file_stem_for(run_name)>/frames.csv, written (atomically) before
// the point's row is committed, so a committed row always has its complete frames.csv and a point
// killed before its row is run again whole.
std::string frames_csv_path(const std::string& out_dir, const std::string& run_name);
// frames.csv read back (merge carries shards' frames into its store): one flat object per line,
// keyed by the header; a blank cell is absent, "inf" in a metric column is null (+infinity), an
// integer cell an integer, any other a double (frames_csv writes the shortest text that reads
// back to the same double). InputError naming the file and line for a ragged line or a cell that
// is not a number.
std::vector<nlohmann::json> read_frames_csv(const std::string& path);

// True for the metric and "true_" metric columns, where null means +infinity (psnr).
bool is_metric_column(const std::string& column);

// Reads a results.json (the rows of ResultsFolder::write): every row checked by unflatten(), a
// run name given twice refused; InputError naming the file and the row or key at fault. Fills
// `context` (when given) from its "context" block.
std::vector<ResultRow> read_results_file(const std::string& path,
                                         std::optional<RunContext>* context = nullptr);

// One output folder's results: <dir>/<stem>.csv and <dir>/<stem>.json. `stem` defaults to
// "results"; give shards of one sweep that share a folder their own stem (e.g.
// "results.shard-1-of-4").
//
// How a row reaches the files (FolderWrites): `whole` rewrites both files atomically (temporary +
// rename) after every row, which costs O(rows) per row; `append` (the runners that may record
// 100,000 rows: sweep, suite, tune, merge) costs O(1) per row: the row is appended as one line to
// <dir>/<stem>.csv (the file is rewritten whole only when the row brings a new column or replaces
// an earlier row) and as one JSON line to the journal <dir>/<stem>.rows.jsonl, while
// <stem>.json is written whole only by write() (a runner's start, resume and end) and by the
// first row this object adds. write() removes the journal after the JSON that holds its rows, so a
// finished run's folder holds the two files CONTRACT §4 names. A run killed between two write()s
// leaves its rows in the journal (and in SQLite: RunRecorder commits there first);
// load_existing() takes them back, ignoring the one partial line an append cut short.
enum class FolderWrites { whole, append };

class ResultsFolder {
 public:
  ResultsFolder(std::string dir, RunContext context, std::string stem = "results",
                FolderWrites writes = FolderWrites::whole);
  // Loads the rows already in <dir>/<stem>.json and its journal (for --resume and merge,
  // read_results_file; a journal row replaces the JSON's row of the same run name) and returns
  // their run names; no file: none. InputError naming the file and the row (or journal line) when
  // it is unreadable, not results JSON, or of a newer schema version. The folder is created by the
  // first write.
  std::vector<std::string> load_existing();
  // The context of <dir>/<stem>.json as load_existing() found it (a resumed sweep keeps its run
  // id, so one sweep is one run however often it was interrupted); empty before loading or when
  // there was no file.
  const std::optional<RunContext>& existing_context() const { return existing_context_; }
  void set_context(const RunContext& context) { context_ = context; }
  // Appends `row` (replacing, in place, a row with the same run_name) and writes it to the files
  // as FolderWrites says.
  // Leaves the point's frames and images as they are (a row taken back from the files by resume).
  void add(const ResultRow& row);
  // The row, its frames and its images in one transaction; the frames and images stored earlier
  // for the same run_id and run_name are replaced.
  void add(const PointRecord& record);
  // A point's frames (in frame order) and kept images (in the order stored); none when the file
  // has no such table.
  std::vector<FrameRow> frames_of(const std::string& run_id, const std::string& run_name);
  std::vector<KeptImage> images_of(const std::string& run_id, const std::string& run_name);
  // Appends `row` when no row has its run_name, without writing the files (resume's repair).
  void merge(const ResultRow& row);
  // Rewrites both files from the rows held (JSON first, then CSV; each atomically), then removes
  // the journal.
  void write();
  const std::vector<ResultRow>& rows() const { return rows_; }
  const RunContext& context() const { return context_; }
  std::string csv_path() const;
  std::string json_path() const;
  std::string journal_path() const;

 private:
  // rows_ grown by `row` (or its run_name's row replaced): true when replaced.
  bool put(const ResultRow& row);
  std::string dir_, stem_;
  FolderWrites writes_;
  RunContext context_;
  std::optional<RunContext> existing_context_;
  std::vector<ResultRow> rows_;
  std::map<std::string, size_t> index_;  // run_name -> position in rows_
  ResultColumns columns_;                // of rows_
  // Whether this object wrote the files since it holds rows_ (so an append continues them), and
  // the CSV header it wrote.
  bool files_current_ = false;
  std::vector<std::string> csv_columns_;
};

// The SQLite history (results_sqlite.cpp; default out/results.sqlite), shared by every run and by
// concurrent shards: WAL journal, busy timeout, one transaction per row, PRAGMA user_version =
// kResultsSchemaVersion plus a `meta` table. Tables:
//   meta(key TEXT PRIMARY KEY, value TEXT)            schema_version, created
//   runs(run_id TEXT PRIMARY KEY, command, machine, device, git_commit, started, context JSON)
//   results(id INTEGER PRIMARY KEY AUTOINCREMENT, <identifying_columns()>, <measured_columns()>,
//           then one column per parameter and per pass, added by ALTER TABLE ADD COLUMN when a
//           row brings a new name)
//   frames(run_id, run_name, frame, <frame_columns()>)   a sequence point's frames
//   (point_record.h),
//           one line per frame, metric columns REAL (one added by ALTER TABLE when a frame brings
//           a key the table lacks)
//   images(run_id, run_name, role, path)   the images a point kept, paths relative to its run's
//           output folder
// frames and images are created in every file opened for writing (a file of an earlier build
// gains them, empty; the schema version is unchanged, readers of it ignore them); a reader of a
// file without them finds no frames and no images.
// A psnr of +infinity (JSON null) is stored as REAL Inf; an absent value as NULL.
class SqliteStore {
 public:
  // read_write creates the parent folders and the database (WAL journal, tables). read_only is for
  // readers of someone's history (the dashboard): it never creates, converts or adds anything, and
  // a file that is missing, corrupt, foreign (no aoeval tables) or of another schema version is an
  // InputError naming it, so the caller can exit 2 and leave the file byte-identical.
  enum class Mode { read_write, read_only };
  // read_write refuses, before writing a byte, a file that is not an aoeval results database
  // (another application's tables, or no SQLite database at all): InputError "--db PATH: not an
  // aoeval results database (...)", the same words as read_only. A new file it created is removed
  // again when opening fails. Throws std::runtime_error with sqlite's message on other failures,
  // and when the database's schema version is newer than this build's.
  explicit SqliteStore(const std::string& path, Mode mode = Mode::read_write);
  ~SqliteStore();
  SqliteStore(const SqliteStore&) = delete;
  SqliteStore& operator=(const SqliteStore&) = delete;

  void add_run(const RunContext& context);  // replaces a run already present
  // One transaction. A row with the same run_id and run_name is replaced, so storing a row twice
  // (a sweep killed between its SQLite commit and its file write, then resumed) keeps one.
  // Leaves the point's frames and images as they are (a row taken back from the files by resume).
  void add(const ResultRow& row);
  // The row, its frames and its images in one transaction; the frames and images stored earlier
  // for the same run_id and run_name are replaced.
  void add(const PointRecord& record);
  // A point's frames (in frame order) and kept images (in the order stored); none when the file
  // has no such table.
  std::vector<FrameRow> frames_of(const std::string& run_id, const std::string& run_name);
  std::vector<KeptImage> images_of(const std::string& run_id, const std::string& run_name);

  std::vector<ResultRow> all_rows();  // in insertion order
  std::vector<ResultRow> rows_of_run(const std::string& run_id);
  std::vector<std::string> run_ids();  // in order of `started`
  std::vector<RunContext> runs();      // likewise
  std::vector<std::string> columns();  // of the results table, in order
  const std::string& path() const { return path_; }

 private:
  std::vector<ResultRow> select_rows(const std::string& sql, const std::string& bound);
  void insert_row(const ResultRow& row);  // inside a transaction (results_sqlite.cpp)
  // Inside a transaction (results_sqlite_frames.cpp).
  void create_point_tables();
  void replace_frames(const ResultRow& row, const std::vector<FrameRow>& frames);
  void replace_images(const ResultRow& row, const std::vector<KeptImage>& images);
  bool has_table(const std::string& name);
  void open_read_only();
  std::string path_;
  sqlite3* db_ = nullptr;
};

// Writers (results_store.cpp). Numbers in CSV use the shortest representation that reads back to
// the same double (std::to_chars); a null metric (psnr = +infinity) is written "inf"; other nulls
// and absent values are blank. Strings are quoted per RFC 4180 when they hold a comma, quote, CR or
// LF. Lines end in "\n".
std::string results_csv(const std::vector<ResultRow>& rows);
// {"schema_version": 1, "context": {...}, "rows": [flat rows, keys in column order]}
std::string results_json(const std::vector<ResultRow>& rows, const RunContext& context);
// Tables of chosen columns (flat column names; absent values blank); numbers to 4 significant
// digits, integers whole.
std::string markdown_table(const std::vector<ResultRow>& rows,
                           const std::vector<std::string>& columns);
std::string console_table(const std::vector<ResultRow>& rows,
                          const std::vector<std::string>& columns);

}  // namespace aoeval
