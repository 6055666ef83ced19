// What one `aoeval run` leaves for its report: the rows, the images the runner kept beside them and
// the G-buffer views it rendered. The runner (harness/sweep/suite_runner.h) fills it; reports/
// (suite_report.h, gbuffer_gallery.h) reads it. Plain data, so reports/ needs no runner to read it.
#pragma once

#include <string>
#include <vector>

#include "harness/results/result_row.h"
#include "harness/results/results_store.h"

namespace aoeval {

struct SuiteReportEntry {
  ResultRow row;          // row.estimate_file is relative to the output folder ("" = not kept)
  bool featured = false;  // shown as a mosaic and in the per-scene tables
  // Relative to the output folder; "" where there is none (a skipped row).
  std::string mosaic_png;
  std::string reference_exr;       // the matched reference
  std::string true_reference_exr;  // the unbounded cosine reference ("true AO")
  // Every file the point kept, by role (point_record.h), as the store holds them: filled by the
  // run reader (suite_record_io.h read_stored_run) for the pages; a runner leaves it empty.
  std::vector<KeptImage> images;
  // The path of the kept file of `role` ("sequence", "frames", "maps", ...); "" when none.
  std::string image(const std::string& role) const {
    for (const KeptImage& k : images)
      if (k.role == role) return k.path;
    return "";
  }
};

// The entry's point record (point_record.h): its row, `frames`, and its images: the estimate
// (from the row, by the recorder), then `sequence_images` (kept_sequence.h), the mosaic, the
// matched and the true reference (roles "mosaic", "reference", "true reference"), those it has.
inline PointRecord point_record(const SuiteReportEntry& entry, std::vector<FrameRow> frames,
                                std::vector<KeptImage> sequence_images) {
  PointRecord record{.row = entry.row, .frames = std::move(frames), .images = {}};
  record.images = std::move(sequence_images);
  const std::pair<const char*, const std::string*> kept[] = {
      {"mosaic", &entry.mosaic_png},
      {"reference", &entry.reference_exr},
      {"true reference", &entry.true_reference_exr}};
  for (const auto& [role, path] : kept)
    if (!path->empty()) record.images.push_back({role, *path});
  return record;
}

struct SuiteReport {
  std::string suite;       // "default"
  std::string suite_file;  // where it was read from
  RunContext context;
  double wall_s = 0.0;
  std::vector<std::string> overrides;  // the --set assignments, as given
  std::vector<SuiteReportEntry> entries;
  std::string gbuffer_gallery;  // relative path of the G-buffer gallery page, "" = none
  bool sweep = false;           // a sweep's rows: its Pareto-front points are the featured ones
};

// One scene view of the G-buffer gallery.
struct GalleryEntry {
  std::string scene;
  std::string view;
  size_t triangles = 0;
  size_t objects = 0;
  double load_ms = 0.0;
  double bvh_ms = 0.0;
  std::string gbuffer_exr;  // relative to the output folder
};

}  // namespace aoeval
