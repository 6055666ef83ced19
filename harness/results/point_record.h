// One evaluated point as it travels from evaluation to the store and every page (issue 46): its
// results row, its frames (a sequence view's, one per frame; a still view's none) and the images
// it kept, each named by its role and its path relative to the run's output folder. The recorder
// stores the whole record in one SQLite transaction (results_store.h: the frames and images
// tables); results.csv/json and frames.csv are exports of it (CONTRACT §4, §10).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/results/result_row.h"

namespace aoeval {

// One frame of a sequence point (one line of its frames.csv). `metrics` and `true_metrics` hold
// the image-family keys of the metric table (metric_table.h), against the matched reference and
// against true AO; null = +infinity (psnr of identical images), absent = not measured.
struct FrameRow {
  int frame = 0;
  double time_ms = 0.0;
  int64_t disoccluded_pixels = 0;
  nlohmann::json metrics = nlohmann::json::object();
  nlohmann::json true_metrics = nlohmann::json::object();
};

// The frame columns in order: frame, time_ms, disoccluded_pixels, then the image-family metric
// keys and the same keys prefixed "true_" (the frames table's columns and frames.csv's header).
const std::vector<std::string>& frame_columns();
// A frame as one flat object keyed by frame_columns() (absent metrics left out), and back.
// frame_row() refuses (InputError naming `where` and the key) a frame without an integer "frame"
// or with a non-numeric value; keys outside frame_columns() are ignored.
nlohmann::json flatten(const FrameRow& frame);
FrameRow frame_row(const nlohmann::json& flat, const std::string& where = "frame");
std::vector<FrameRow> frame_rows(const std::vector<nlohmann::json>& flat);
std::vector<nlohmann::json> flatten(const std::vector<FrameRow>& frames);

// A file a point kept: `role` says what it is ("estimate", "mosaic", "reference", "true
// reference", "frame 0007 estimate", "frame 0007 reference", "maps"; a sequence point's manifest
// "sequence" and its "frames" CSV), `path` where it is, relative to the run's output folder. The
// pages find a point's files by role, never by rebuilding a path.
struct KeptImage {
  std::string role;
  std::string path;
  bool operator==(const KeptImage&) const = default;
};

struct PointRecord {
  ResultRow row;
  std::vector<FrameRow> frames;   // in frame order; empty for a still view
  std::vector<KeptImage> images;  // the row's estimate_file among them when it kept one
};

// The role of a kept sequence frame's image: "frame 0007 estimate", "frame 0007 reference".
std::string frame_image_role(int frame, const std::string& what);

}  // namespace aoeval
