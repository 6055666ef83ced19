#include "harness/results/suite_record_io.h"

#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "base/text_files.h"
#include "harness/results/results_store.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {
const char* kFile = "suite_record.json";
}

void write_suite_record(const std::string& out_dir, const SuiteReport& report,
                        const std::vector<GalleryEntry>& gallery) {
  nlohmann::json j;
  j["suite"] = report.suite;
  j["suite_file"] = report.suite_file;
  j["overrides"] = report.overrides;
  j["wall_s"] = report.wall_s;
  nlohmann::json entries = nlohmann::json::array();
  for (const SuiteReportEntry& e : report.entries)
    entries.push_back({{"run_name", e.row.run_name},
                       {"featured", e.featured},
                       {"mosaic_png", e.mosaic_png},
                       {"reference_exr", e.reference_exr},
                       {"true_reference_exr", e.true_reference_exr}});
  j["entries"] = entries;
  nlohmann::json views = nlohmann::json::array();
  for (const GalleryEntry& g : gallery)
    views.push_back({{"scene", g.scene},
                     {"view", g.view},
                     {"triangles", g.triangles},
                     {"objects", g.objects},
                     {"load_ms", g.load_ms},
                     {"bvh_ms", g.bvh_ms},
                     {"gbuffer_exr", g.gbuffer_exr}});
  j["gallery"] = views;
  write_text((fs::path(out_dir) / kFile).string(), j.dump(1) + "\n");
}

bool has_suite_record(const std::string& dir) {
  std::error_code ec;
  return fs::exists(fs::path(dir) / kFile, ec);
}

SuiteRecordFile read_suite_record(const std::string& dir) {
  const std::string path = (fs::path(dir) / kFile).string();
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  SuiteRecordFile r;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    r.suite = j.at("suite").get<std::string>();
    r.suite_file = j.at("suite_file").get<std::string>();
    r.overrides = j.at("overrides").get<std::vector<std::string>>();
    r.wall_s = j.at("wall_s").get<double>();
    for (const auto& e : j.at("entries")) {
      SuiteReportEntry entry;
      entry.featured = e.at("featured").get<bool>();
      entry.mosaic_png = e.at("mosaic_png").get<std::string>();
      entry.reference_exr = e.at("reference_exr").get<std::string>();
      entry.true_reference_exr = e.at("true_reference_exr").get<std::string>();
      r.entries[e.at("run_name").get<std::string>()] = entry;
    }
    for (const auto& g : j.at("gallery")) {
      GalleryEntry v;
      v.scene = g.at("scene").get<std::string>();
      v.view = g.at("view").get<std::string>();
      v.triangles = g.at("triangles").get<size_t>();
      v.objects = g.at("objects").get<size_t>();
      v.load_ms = g.at("load_ms").get<double>();
      v.bvh_ms = g.at("bvh_ms").get<double>();
      v.gbuffer_exr = g.at("gbuffer_exr").get<std::string>();
      r.gallery.push_back(v);
    }
  } catch (const std::exception& e) {
    throw InputError(path + ": not a suite record (" + e.what() + ")");
  }
  return r;
}

StoredRun read_stored_run(const std::string& dir, const std::string& database) {
  const SuiteRecordFile record = read_suite_record(dir);
  ResultsFolder folder(dir, RunContext{});
  folder.load_existing();
  SqliteStore store(database, SqliteStore::Mode::read_only);
  StoredRun run;
  SuiteReport& report = run.report;
  report.suite = record.suite;
  report.suite_file = record.suite_file;
  report.overrides = record.overrides;
  report.wall_s = record.wall_s;
  if (const auto& context = folder.existing_context()) report.context = *context;
  for (const ResultRow& row : folder.rows()) {
    SuiteReportEntry entry;
    if (const auto it = record.entries.find(row.run_name); it != record.entries.end())
      entry.featured = it->second.featured;
    entry.row = row;
    entry.images =
        store.images_of(row.run_id.empty() ? report.context.run_id : row.run_id, row.run_name);
    entry.mosaic_png = entry.image("mosaic");
    entry.reference_exr = entry.image("reference");
    entry.true_reference_exr = entry.image("true reference");
    report.entries.push_back(std::move(entry));
  }
  run.gallery = record.gallery;
  return run;
}

}  // namespace aoeval
