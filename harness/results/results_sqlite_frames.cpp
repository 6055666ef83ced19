// The frames and images tables of SqliteStore (results_store.h): a point's frames and kept images,
// stored in the transaction of its row and read back by the pages.
#include <set>

#include "harness/results/results_store.h"
#include "harness/results/sqlite_statement.h"

namespace aoeval {

using namespace sqlite_detail;

namespace {

// Counts are INTEGER, the rest REAL (a value keeps the type it was bound with).
std::string frame_column_type(const std::string& column) {
  static const std::set<std::string> integers = {"frame", "disoccluded_pixels", "pixels",
                                                 "true_pixels"};
  return integers.count(column) ? " INTEGER" : " REAL";
}

}  // namespace

void SqliteStore::create_point_tables() {
  std::string create =
      "CREATE TABLE IF NOT EXISTS frames (run_id TEXT NOT NULL, run_name TEXT NOT NULL";
  for (const auto& c : frame_columns()) create += ", " + quote_identifier(c) + frame_column_type(c);
  exec(db_, path_, create + ", PRIMARY KEY (run_id, run_name, frame))");
  exec(db_, path_,
       "CREATE TABLE IF NOT EXISTS images (run_id TEXT NOT NULL, run_name TEXT NOT NULL, "
       "role TEXT NOT NULL, path TEXT NOT NULL, PRIMARY KEY (run_id, run_name, role))");
}

bool SqliteStore::has_table(const std::string& name) {
  Statement s(db_, path_, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?");
  s.bind_text(1, name);
  return s.step() && sqlite3_column_int(s.get(), 0) == 1;
}

void SqliteStore::replace_frames(const ResultRow& row, const std::vector<FrameRow>& frames) {
  Statement drop(db_, path_, "DELETE FROM frames WHERE run_id = ? AND run_name = ?");
  drop.bind_text(1, row.run_id);
  drop.bind_text(2, row.run_name);
  drop.step();
  if (frames.empty()) return;
  // A column the metric table gained since the file was made is added, as results' are.
  std::set<std::string> present;
  {
    Statement info(db_, path_, "PRAGMA table_info(frames)");
    while (info.step()) present.insert(info.text(1));
  }
  for (const auto& c : frame_columns())
    if (!present.count(c))
      exec(db_, path_,
           "ALTER TABLE frames ADD COLUMN " + quote_identifier(c) + frame_column_type(c));
  std::string sql = "INSERT INTO frames (run_id, run_name", marks = "?, ?";
  for (const auto& c : frame_columns()) {
    sql += ", " + quote_identifier(c);
    marks += ", ?";
  }
  Statement insert(db_, path_, sql + ") VALUES (" + marks + ")");
  for (const FrameRow& f : frames) {
    const nlohmann::json flat = flatten(f);
    sqlite3_reset(insert.get());
    sqlite3_clear_bindings(insert.get());
    insert.bind_text(1, row.run_id);
    insert.bind_text(2, row.run_name);
    int i = 3;
    for (const auto& c : frame_columns()) {
      const auto it = flat.find(c);
      if (it != flat.end()) insert.bind_json(i, *it, c);  // absent: NULL
      ++i;
    }
    insert.step();
  }
}

void SqliteStore::replace_images(const ResultRow& row, const std::vector<KeptImage>& images) {
  Statement drop(db_, path_, "DELETE FROM images WHERE run_id = ? AND run_name = ?");
  drop.bind_text(1, row.run_id);
  drop.bind_text(2, row.run_name);
  drop.step();
  Statement insert(
      db_, path_,
      "INSERT OR REPLACE INTO images (run_id, run_name, role, path) VALUES (?, ?, ?, ?)");
  for (const KeptImage& image : images) {
    sqlite3_reset(insert.get());
    insert.bind_text(1, row.run_id);
    insert.bind_text(2, row.run_name);
    insert.bind_text(3, image.role);
    insert.bind_text(4, image.path);
    insert.step();
  }
}

std::vector<FrameRow> SqliteStore::frames_of(const std::string& run_id,
                                             const std::string& run_name) {
  std::vector<FrameRow> out;
  if (!has_table("frames")) return out;
  Statement s(db_, path_, "SELECT * FROM frames WHERE run_id = ? AND run_name = ? ORDER BY frame");
  s.bind_text(1, run_id);
  s.bind_text(2, run_name);
  while (s.step()) {
    nlohmann::json flat = nlohmann::json::object();
    for (int i = 0; i < sqlite3_column_count(s.get()); ++i) {
      const std::string name = sqlite3_column_name(s.get(), i);
      const int type = sqlite3_column_type(s.get(), i);
      if (name == "run_id" || name == "run_name" || type == SQLITE_NULL) continue;
      if (type == SQLITE_INTEGER) {
        flat[name] = static_cast<int64_t>(sqlite3_column_int64(s.get(), i));
      } else {
        const double v = sqlite3_column_double(s.get(), i);
        flat[name] =
            std::isinf(v) && is_metric_column(name) ? nlohmann::json(nullptr) : nlohmann::json(v);
      }
    }
    out.push_back(frame_row(flat, "--db " + path_ + ": frames[" + run_name + "]"));
  }
  return out;
}

std::vector<KeptImage> SqliteStore::images_of(const std::string& run_id,
                                              const std::string& run_name) {
  std::vector<KeptImage> out;
  if (!has_table("images")) return out;
  Statement s(db_, path_,
              "SELECT role, path FROM images WHERE run_id = ? AND run_name = ? ORDER BY rowid");
  s.bind_text(1, run_id);
  s.bind_text(2, run_name);
  while (s.step()) out.push_back({s.text(0), s.text(1)});
  return out;
}

}  // namespace aoeval
