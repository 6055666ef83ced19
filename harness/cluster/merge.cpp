#include "harness/cluster/merge.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "base/errors.h"
#include "base/json_reader.h"
#include "harness/results/run_recorder.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/shard_plan.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string row_conflict(const ResultRow& a, const ResultRow& b) {
  if (a.params != b.params) return "params";
  if (a.definition != b.definition) return "definition";
  if (a.reference != b.reference) return "reference";
  if (a.status != b.status) return "status";
  auto differ = [](const nlohmann::json& x, const nlohmann::json& y) -> std::string {
    std::set<std::string> keys;
    for (auto it = x.begin(); it != x.end(); ++it) keys.insert(it.key());
    for (auto it = y.begin(); it != y.end(); ++it) keys.insert(it.key());
    for (const auto& k : keys)
      if (!x.contains(k) || !y.contains(k) || x.at(k) != y.at(k)) return k;
    return "";
  };
  if (const std::string k = differ(a.metrics, b.metrics); !k.empty()) return k;
  if (const std::string k = differ(a.true_metrics, b.true_metrics); !k.empty()) return "true_" + k;
  return "";
}

namespace {

double ratio(const std::vector<double>& v) {
  double sum = 0.0, most = 0.0;
  for (double x : v) {
    sum += x;
    most = std::max(most, x);
  }
  return sum > 0.0 ? most / (sum / static_cast<double>(v.size())) : 0.0;
}

// Copies the images a folder's rows and report point at (estimates, runs/<id>/, references,
// G-buffers) into the merged folder; a file already there (the same reference from another shard)
// is kept.
void copy_images(const fs::path& from, const fs::path& to) {
  for (const char* sub : {"estimates", "runs", "references", "gbuffers/scenes", "sequences"}) {
    const fs::path src = from / sub;
    std::error_code ec;
    if (!fs::is_directory(src, ec)) continue;
    fs::create_directories(to / sub);
    fs::copy(src, to / sub, fs::copy_options::recursive | fs::copy_options::skip_existing, ec);
    if (ec) throw std::runtime_error("merge: cannot copy " + src.string() + ": " + ec.message());
  }
}

// A row of `dir` as a whole point, as the shard's recorder stored it (suite_record.h
// point_record): the estimate, a sequence point's kept frames and maps (its sequence.json), then
// the mosaic and references of its report entry (`entry`, from the shard's suite_record.json), and
// a sequence point's frames (its metrics hold seq_frames) from its frames.csv, found where the
// runner wrote it (results_store.h frames_csv_path: <dir>/sequences/... for a sweep,
// <dir>/runs/<its run id>/... for a suite run). Paths are relative to the folder, so they hold in
// the merged one, where copy_images() puts the files. A sequence point without its frames.csv is
// an InputError naming the file (a shard whose folder lost it).
PointRecord point_of(const std::string& dir, const ResultRow& row, const SuiteReportEntry* entry) {
  std::vector<FrameRow> frames;
  std::vector<KeptImage> sequence_images;
  if (row.metrics.contains("seq_frames")) {
    fs::path csv, csv_rel;  // csv_rel: relative to `dir`, as kept_sequence.cpp names it
    for (const std::string& base : {std::string("."), "runs/" + row.run_id})
      if (const fs::path rel = fs::path(frames_csv_path(base, row.run_name)).lexically_normal();
          fs::exists(fs::path(dir) / rel)) {
        csv = fs::path(dir) / rel;
        csv_rel = rel;
        break;
      }
    if (csv.empty())
      throw InputError("merge: " + row.run_name + " is a sequence point but " +
                       frames_csv_path(dir, row.run_name) + " is missing");
    frames = frame_rows(read_frames_csv(csv.string()));
    if (const fs::path manifest_path = csv.parent_path() / "sequence.json";
        fs::exists(manifest_path)) {
      const nlohmann::json manifest = parse_json_file(manifest_path.string());
      for (const auto& kept : manifest.value("kept", nlohmann::json::array()))
        for (const char* what : {"estimate", "reference"})
          if (kept.contains(what))
            sequence_images.push_back(
                {frame_image_role(kept.value("frame", 0), what), kept[what].get<std::string>()});
      if (manifest.contains("maps")) sequence_images.push_back({"maps", manifest["maps"]});
      sequence_images.push_back({"sequence", (csv_rel.parent_path() / "sequence.json").string()});
    }
    sequence_images.push_back({"frames", csv_rel.string()});
  }
  SuiteReportEntry with_row = entry ? *entry : SuiteReportEntry{};
  with_row.row = row;
  return point_record(with_row, std::move(frames), std::move(sequence_images));
}

std::optional<ShardTiming> read_timing(const std::string& dir) {
  const fs::path path = fs::path(dir) / "shard.json";
  if (!fs::exists(path)) return std::nullopt;
  // Written by the shard's job script (slurm_submit.cpp): {"index", "count", "node", "wall_s"}.
  JsonReader r(parse_json_file(path.string()), path.string());
  ShardTiming t;
  t.dir = dir;
  t.index = static_cast<int>(r.integer("index", 0, 1000000));
  r.integer("count", 1, 1000001);
  t.wall_s = r.number("wall_s", 0.0, 1e9);
  t.node = r.string("node", "");
  r.finish();
  return t;
}

}  // namespace

MergeResult merge_results(const MergeOptions& o) {
  if (o.dirs.empty()) throw InputError("merge: give at least one folder to merge");
  if (o.out.empty()) throw InputError("merge: --out is required");
  struct Found {
    ResultRow row;
    size_t dir;
  };
  std::map<std::string, Found> by_name;
  std::vector<std::string> order;
  MergeResult result;
  result.out = o.out;
  std::vector<std::optional<SuiteRecordFile>> records;
  for (size_t d = 0; d < o.dirs.size(); ++d) {
    const std::string& dir = o.dirs[d];
    if (!fs::exists(fs::path(dir) / "results.json") && !o.plan.empty()) {
      std::fprintf(stderr, "merge: %s: no results.json (its shard never started)\n", dir.c_str());
      records.push_back(std::nullopt);
      continue;  // the plan check below names what it lacks
    }
    if (!fs::exists(fs::path(dir) / "results.json"))
      throw InputError(dir +
                       ": no results.json (not an aoeval output folder, or a shard that "
                       "never started)");
    ResultsFolder folder(dir, RunContext{});
    folder.load_existing();
    for (const ResultRow& r : folder.rows()) {
      auto [it, fresh] = by_name.emplace(r.run_name, Found{r, d});
      if (fresh) {
        order.push_back(r.run_name);
        continue;
      }
      const std::string field = row_conflict(it->second.row, r);
      if (!field.empty())
        throw InputError("merge: row " + r.run_name + " is in " + o.dirs[it->second.dir] +
                         " and in " + dir + " with different values (" + field + ")");
      ++result.duplicates;
    }
    records.push_back(has_suite_record(dir) ? std::optional(read_suite_record(dir)) : std::nullopt);
    if (auto t = read_timing(dir)) result.timings.push_back(*t);
  }

  if (!o.plan.empty()) {
    const ShardPlan plan = read_shard_plan(o.plan);
    result.planned_ratio = plan.planned_ratio();
    std::map<int, size_t> missing;
    std::vector<std::string> planned;
    for (size_t i = 0; i < plan.points.size(); ++i) {
      planned.push_back(plan.points[i].name);
      if (!by_name.count(plan.points[i].name)) ++missing[plan.shard_of[i]];
    }
    if (!missing.empty()) {
      std::string what;
      for (const auto& [shard, n] : missing)
        what += (what.empty() ? "" : "; ") + std::string("shard ") + std::to_string(shard) +
                " of " + std::to_string(plan.shards) + " lacks " + std::to_string(n) + " point" +
                (n == 1 ? "" : "s");
      throw std::runtime_error(
          "merge: incomplete: " + what + " (see its job log); the finished shards' rows are kept " +
          "in their folders: resubmit with --resume to run only what is missing");
    }
    for (auto it = planned.begin(); it != planned.end();)  // plan order = single-machine order
      it = by_name.count(*it) ? std::next(it) : planned.erase(it);
    for (const auto& n : order)
      if (std::find(planned.begin(), planned.end(), n) == planned.end()) planned.push_back(n);
    order = planned;
    for (ShardTiming& t : result.timings)
      if (t.index >= 0 && static_cast<size_t>(t.index) < plan.shard_ms.size())
        t.planned_ms = plan.shard_ms[static_cast<size_t>(t.index)];
  }
  if (!result.timings.empty()) {
    std::vector<double> walls;
    for (const auto& t : result.timings) walls.push_back(t.wall_s);
    result.measured_ratio = ratio(walls);
  }

  // Each point whole: a sequence point's frames and kept images from its shard's folder.
  std::vector<PointRecord> points;
  for (const auto& n : order) {
    const Found& found = by_name.at(n);
    const SuiteReportEntry* entry = nullptr;
    if (const auto& rec = records[found.dir]; rec)
      if (const auto it = rec->entries.find(n); it != rec->entries.end()) entry = &it->second;
    points.push_back(point_of(o.dirs[found.dir], found.row, entry));
  }

  // Inputs all read and checked above; the store is opened last. The rows already carry their
  // identity (each keeps the machine, device and commit of the shard that measured it): they take
  // the merge's run id, one run in the history, and are imported as they are, not stamped.
  std::string command = "merge";
  for (const auto& d : o.dirs) command += " " + d;
  RunRecorder recorder(o.out, o.database, command, FolderAccess::exclusive);
  recorder.context().output_dir = fs::weakly_canonical(fs::absolute(o.out)).string();
  result.context = recorder.context();
  for (PointRecord& point : points) {
    point.row.run_id = result.context.run_id;
    result.rows.push_back(point.row);
  }
  for (const auto& d : o.dirs)
    if (fs::weakly_canonical(fs::absolute(d)) != fs::weakly_canonical(fs::absolute(o.out)))
      copy_images(d, o.out);
  recorder.import_records(points);

  if (!result.timings.empty() || result.planned_ratio > 0.0) {
    nlohmann::json shards = nlohmann::json::array();
    for (const ShardTiming& t : result.timings)
      shards.push_back({{"index", t.index},
                        {"node", t.node},
                        {"wall_s", t.wall_s},
                        {"planned_ms", t.planned_ms},
                        {"dir", t.dir}});
    write_text((fs::path(o.out) / "shard_times.json").string(),
               nlohmann::json{{"shards", shards},
                              {"measured_ratio", result.measured_ratio},
                              {"planned_ratio", result.planned_ratio}}
                       .dump(1) +
                   "\n");
  }

  const bool suite = !records.empty() && std::all_of(records.begin(), records.end(),
                                                     [](const auto& r) { return r.has_value(); });
  if (suite) {
    SuiteReport report;
    report.suite = records.front()->suite;
    report.suite_file = records.front()->suite_file;
    report.overrides = records.front()->overrides;
    report.context = result.context;
    for (const auto& r : records) report.wall_s = std::max(report.wall_s, r->wall_s);
    std::set<std::string> views;
    std::map<std::string, GalleryEntry> gallery_by_file;
    std::vector<GalleryEntry> gallery;
    for (const auto& r : records)
      for (const auto& g : r->gallery) gallery_by_file.emplace(g.gbuffer_exr, g);
    for (const ResultRow& row : result.rows) {
      const auto& rec = records[by_name.at(row.run_name).dir];
      SuiteReportEntry entry;
      if (auto it = rec->entries.find(row.run_name); it != rec->entries.end()) entry = it->second;
      entry.row = row;
      report.entries.push_back(entry);
      // The gallery in the order of first use, as suite_runner.cpp builds it.
      const std::string file = "scenes/" + row.scene + "/" + row.view + "_" +
                               std::to_string(row.width) + "x" + std::to_string(row.height) +
                               "_gbuffer.exr";
      if (row.status == "ok" && gallery_by_file.count(file) && views.insert(file).second)
        gallery.push_back(gallery_by_file.at(file));
    }
    // The merged folder's record (it can be merged again), then its pages from the store, the
    // folder still locked.
    write_suite_record(o.out, report, gallery);
    if (o.pages) result.page = o.pages(o.out, o.database);
  }
  return result;
}

}  // namespace aoeval
