// `aoeval compare --sequence` (compare_sequence.h): the §10 keys of two frame folders against
// numbers worked out by hand, the keys a sequence sweep stored for its row reproduced from the
// frames it kept, and bad folders refused with exit 2 naming the file.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/exr_io.h"
#include "scenes/gbuffer.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::Result;
using aoeval::cli_test::run_aoeval;
using aoeval::cli_test::slurp;

Result run(const std::string& args, const fs::path& d) {
  return run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " ", args, d);
}

std::string frame_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", k);
  return name;
}

// A w x h AO EXR: AO = ao, A = 1 except pixel 0 (uncovered), AO_stderr = stderr when given.
void write_frame(const fs::path& path, int w, int h, float ao,
                 std::optional<float> stderr_ao = std::nullopt) {
  const bool with_stderr = stderr_ao.has_value();
  OIIO::ImageSpec spec(w, h, with_stderr ? 3 : 2, OIIO::TypeDesc::FLOAT);
  spec.channelnames = with_stderr ? std::vector<std::string>{"AO", "A", "AO_stderr"}
                                  : std::vector<std::string>{"AO", "A"};
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  for (int p = 0; p < w * h; ++p) {
    float* o = px + p * spec.nchannels;
    o[0] = p == 0 ? 1.0f : ao;  // the uncovered pixel's AO must not count
    o[1] = p == 0 ? 0.0f : 1.0f;
    if (with_stderr) o[2] = *stderr_ao;
  }
  fs::create_directories(path.parent_path());
  aoeval::write_exr(path.string(), image, {});
}

// Three static frames: ref 0.5 + 0.001 k (independent traces: their bits differ) with stderr
// 0.01 everywhere, est = ref + (+0.1, -0.1, +0.1). Each frame's rmse is 0.1, its rmse_excess
// sqrt(0.1^2 - 0.01^2); the frame-to-frame differences d = e_k - e_{k-1} are -0.2, +0.2, so
// temporal_rmse = 0.2 and temporal_rmse_excess = sqrt(0.2^2 - 2 * 0.01^2); the error is the same
// every frame, so converge_frames = 0; nothing is disoccluded, so settle_frames and
// disocclusion_rmse_excess are null.
TEST(CompareSequence, StaticFramesGiveTheWorkedOutKeys) {
  const fs::path d = aoeval::testutil::test_temp_dir("compare_sequence");
  const float offsets[3] = {0.1f, -0.1f, 0.1f};
  for (int k = 0; k < 3; ++k) {
    write_frame(d / "ref" / frame_name(k), 4, 3, 0.5f + 0.001f * k, 0.01f);
    write_frame(d / "est" / frame_name(k), 4, 3, 0.5f + 0.001f * k + offsets[k]);
  }
  std::ofstream(d / "ref" / "notes.txt") << "other files are ignored";
  const Result r = run("compare --sequence " + (d / "ref").string() + " " + (d / "est").string() +
                           " --static --json " + (d / "keys.json").string(),
                       d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto keys = nlohmann::json::parse(slurp(d / "keys.json"));
  // float32 AO: 0.5 + 0.1 is 0.6000000238..., so the tolerance is float rounding, 1e-6.
  const double excess = std::sqrt(0.01 - 1e-4), temporal = std::sqrt(0.04 - 2e-4);
  EXPECT_EQ(keys["seq_frames"], 3);
  EXPECT_NEAR(keys["seq_rmse_excess"].get<double>(), excess, 1e-6);
  EXPECT_NEAR(keys["steady_rmse_excess"].get<double>(), excess, 1e-6);
  EXPECT_NEAR(keys["temporal_rmse"].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(keys["temporal_rmse_excess"].get<double>(), temporal, 1e-6);
  EXPECT_EQ(keys["converge_frames"], 0);
  EXPECT_TRUE(keys["settle_frames"].is_null());
  EXPECT_TRUE(keys["disocclusion_rmse_excess"].is_null());
  ASSERT_EQ(keys["rmse_excess_by_frame"].size(), 3u);
  for (const auto& v : keys["rmse_excess_by_frame"]) EXPECT_NEAR(v.get<double>(), excess, 1e-6);
  // Without --json the same keys go to stdout.
  const Result printed = run(
      "compare --sequence " + (d / "ref").string() + " " + (d / "est").string() + " --static", d);
  ASSERT_EQ(printed.code, 0) << printed.err;
  EXPECT_EQ(nlohmann::json::parse(printed.out), keys);
}

// A reference repeated bit for bit (a static frame's reference reused, issue 42; a run keeps it
// as a hard link) is one trace: its noise is shared, so the temporal keys remove none of it, as
// the session's scoring does (TemporalScores.RepeatedReferenceRemovesNoNoise). The frames above
// with one reference, 0.5, for all three: temporal_rmse_excess is the whole 0.2, while each
// frame's own rmse_excess still removes its stderr.
TEST(CompareSequence, ARepeatedReferenceRemovesNoNoiseFromTheTemporalKeys) {
  const fs::path d = aoeval::testutil::test_temp_dir("compare_sequence_repeated");
  const float offsets[3] = {0.1f, -0.1f, 0.1f};
  for (int k = 0; k < 3; ++k) {
    write_frame(d / "ref" / frame_name(k), 4, 3, 0.5f, 0.01f);
    write_frame(d / "est" / frame_name(k), 4, 3, 0.5f + offsets[k]);
  }
  const Result r = run(
      "compare --sequence " + (d / "ref").string() + " " + (d / "est").string() + " --static", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto keys = nlohmann::json::parse(r.out);
  EXPECT_NEAR(keys["temporal_rmse"].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(keys["temporal_rmse_excess"].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(keys["seq_rmse_excess"].get<double>(), std::sqrt(0.01 - 1e-4), 1e-6);
}

TEST(CompareSequence, BadFoldersExitTwoNamingTheFile) {
  const fs::path d = aoeval::testutil::test_temp_dir("compare_sequence_bad");
  for (int k = 0; k < 3; ++k) {
    write_frame(d / "ref" / frame_name(k), 4, 3, 0.5f, 0.01f);
    write_frame(d / "est" / frame_name(k), 4, 3, 0.4f);
  }
  const std::string ref = (d / "ref").string(), est = (d / "est").string();
  auto expect_refused = [&](const std::string& args, const std::string& named) {
    SCOPED_TRACE(args);
    const Result r = run("compare --sequence " + args, d);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "keys.json"));
  };
  // Neither --motion nor --static: moving frames would silently be scored as still.
  expect_refused(ref + " " + est + " --json " + (d / "keys.json").string(), "--static");
  expect_refused(ref + " " + est + " --static --motion " + ref, "--static");
  expect_refused(ref + " " + est + " --static --mosaic " + (d / "m.png").string(), "--mosaic");
  expect_refused(ref + " " + (d / "nowhere").string() + " --static", "nowhere");
  // A gap: frame 1 missing in the estimates.
  fs::rename(d / "est" / frame_name(1), d / "est-frame1.exr");
  expect_refused(ref + " " + est + " --static", (d / "est" / frame_name(1)).string());
  // One frame fewer than the references.
  fs::rename(d / "est" / frame_name(2), d / "est" / frame_name(1));
  expect_refused(ref + " " + est + " --static", (d / "est" / frame_name(2)).string());
  // One frame more.
  write_frame(d / "est" / frame_name(2), 4, 3, 0.4f);
  write_frame(d / "est" / frame_name(3), 4, 3, 0.4f);
  expect_refused(ref + " " + est + " --static", frame_name(3));
  fs::remove(d / "est" / frame_name(3));
  // A frame of another size.
  write_frame(d / "est" / frame_name(2), 5, 3, 0.4f);
  expect_refused(ref + " " + est + " --static", (d / "est" / frame_name(2)).string());
  write_frame(d / "est" / frame_name(2), 4, 3, 0.4f);
  ASSERT_EQ(run("compare --sequence " + ref + " " + est + " --static", d).code, 0);
  // --static outside --sequence.
  const Result still = run(
      "compare " + ref + "/" + frame_name(0) + " " + est + "/" + frame_name(0) + " --static", d);
  EXPECT_EQ(still.code, 2) << still.err;
  EXPECT_NE(still.err.find("--sequence"), std::string::npos) << still.err;
}

// A w x h sequence G-buffer (coverage as write_frame's, pixel 0 uncovered) whose motion is
// (0.25, 0) everywhere except `motion_x` at pixel (2, 1).
void write_gbuffer(const fs::path& path, int w, int h, float motion_x) {
  aoeval::GBuffer g;
  g.width = w;
  g.height = h;
  const size_t n = g.pixel_count();
  g.coverage.assign(n, 1.0f);
  g.coverage[0] = 0.0f;
  g.depth.assign(n, 1.0f);
  g.position.assign(n, glm::vec3(0.0f, 0.0f, -1.0f));
  g.normal.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
  g.geometric_normal = g.normal;
  g.object_id.assign(n, 0.0f);
  g.motion.assign(n, glm::vec2(0.25f, 0.0f));
  g.motion[g.index(2, 1)].x = motion_x;
  g.disoccluded.assign(n, 0.0f);
  fs::create_directories(path.parent_path());
  aoeval::write_exr(path.string(), aoeval::gbuffer_to_image(g),
                    {{"aoeval:camera", aoeval::camera_to_json(g.camera)}});
}

// Damaged frames are exit 2 naming the file and the pixel, never a score: NaN or infinite motion
// on a covered pixel (NaN crashed the scorer, inf passed as off screen), and a reference stderr
// that is NaN, infinite, negative or above 0.5 (each scored as perfect: rmse_excess 0). The
// single-image compare reads references the same way.
TEST(CompareSequence, DamagedMotionOrStderrExitsTwoNamingFileAndPixel) {
  const fs::path d = aoeval::testutil::test_temp_dir("compare_sequence_damaged");
  for (int k = 0; k < 3; ++k) {
    write_frame(d / "ref" / frame_name(k), 4, 3, 0.5f, 0.01f);
    write_frame(d / "est" / frame_name(k), 4, 3, 0.4f);
    write_gbuffer(d / "g" / frame_name(k), 4, 3, 0.25f);
  }
  const std::string ref = (d / "ref").string(), est = (d / "est").string(),
                    motion = " --motion " + (d / "g").string();
  ASSERT_EQ(run("compare --sequence " + ref + " " + est + motion, d).code, 0);
  auto expect_refused = [&](const std::string& args, const std::string& named) {
    SCOPED_TRACE(args);
    const Result r = run(args, d);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  const std::string g1 = (d / "g" / frame_name(1)).string();
  for (const auto& [value, text] : std::vector<std::pair<float, std::string>>{
           {std::nanf(""), "NaN"}, {INFINITY, "inf"}, {-INFINITY, "-inf"}}) {
    write_gbuffer(g1, 4, 3, value);
    expect_refused("compare --sequence " + ref + " " + est + motion,
                   g1 + ": motion.X is " + text + " at covered pixel (2, 1)");
  }
  write_gbuffer(g1, 4, 3, 0.25f);
  const std::string r2 = (d / "ref" / frame_name(2)).string();
  for (const auto& [value, text] : std::vector<std::pair<float, std::string>>{
           {std::nanf(""), "nan"}, {INFINITY, "inf"}, {-1.0f, "-1"}, {100.0f, "100"}}) {
    write_frame(r2, 4, 3, 0.5f, value);
    const std::string named = r2 + ": AO_stderr value " + text + " at pixel (1, 0)";
    expect_refused("compare --sequence " + ref + " " + est + " --static", named);
    expect_refused("compare " + r2 + " " + (d / "est" / frame_name(2)).string(), named);
  }
}

// A sequence sweep keeps each point's estimate frames and their references in compare's layout
// (harness/sweep/kept_sequence.h); with the frames' G-buffers from `aoeval gbuffer --frame K`,
// compare --sequence gives back the keys of the sweep's row (the same floats, the same scorer).
TEST(CompareSequence, ReproducesTheKeysASequenceSweepStored) {
  const fs::path d = aoeval::testutil::test_temp_dir("compare_sequence_sweep");
  std::ofstream(d / "slide.json") << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.5, 0.5, 0.5]}}],
    "views": [{"name": "slide", "eye": [0, 1.2, 1.6], "target": [0, 0.2, 0], "fov_y_deg": 50,
               "width": 32, "height": 24,
               "sequence": {"frames": 5, "fps": 30,
                 "camera": [{"frame": 4, "eye": [0.3, 1.2, 1.6], "target": [0.1, 0.2, 0]}],
                 "objects": {"box": [{"frame": 0, "translate": [-0.3, 0, 0]},
                                     {"frame": 4, "translate": [0.3, 0, 0]}]}}}]})";
  const nlohmann::json spec = {{"name", "cmp-seq"},
                               {"scenes", {(d / "slide.json").string()}},
                               {"views", {"slide"}},
                               {"reference", {{"spp", 16}, {"sampler", "sobol"}}},
                               {"timing", {{"warmup", 0}, {"repetitions", 1}}},
                               {"runs", {{{"estimator", "raytraced"}, {"fixed", {{"rays", 2}}}}}}};
  std::ofstream(d / "spec.json") << spec.dump();
  const fs::path out = d / "out";
  const Result sweep = run("sweep " + (d / "spec.json").string() + " --out " + out.string() +
                               " --db " + (d / "r.sqlite").string(),
                           d);
  ASSERT_EQ(sweep.code, 0) << sweep.err;
  const auto row = nlohmann::json::parse(slurp(out / "results.json"))["rows"][0];
  const std::string stem = row["estimate_file"].get<std::string>().substr(10);  // "estimates/"
  const fs::path est_dir = out / "sequences" / stem.substr(0, stem.size() - 4);
  const auto manifest = nlohmann::json::parse(slurp(est_dir / "sequence.json"));
  const fs::path ref_dir =
      out / fs::path(manifest["kept"][0]["reference"].get<std::string>()).parent_path();
  for (int k = 0; k < 5; ++k)
    ASSERT_EQ(run("gbuffer --scene " + (d / "slide.json").string() + " --view slide --frame " +
                      std::to_string(k) + " -o " + (d / "g" / frame_name(k)).string(),
                  d)
                  .code,
              0);
  const Result r = run("compare --sequence " + ref_dir.string() + " " + est_dir.string() +
                           " --motion " + (d / "g").string(),
                       d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto keys = nlohmann::json::parse(r.out);
  EXPECT_GT(row["disocclusion_rmse_excess"].get<double>(), 0.0) << "the box uncovers floor";
  for (const char* k : {"seq_frames", "seq_rmse_excess", "steady_rmse_excess", "temporal_rmse",
                        "temporal_rmse_excess", "converge_frames", "settle_frames",
                        "disocclusion_rmse_excess", "lag_rmse_excess"}) {
    SCOPED_TRACE(k);
    if (row[k].is_null()) {
      EXPECT_TRUE(keys[k].is_null());
      continue;
    }
    // The results files print 17 significant digits: equal to their rounding.
    EXPECT_NEAR(keys[k].get<double>(), row[k].get<double>(),
                1e-12 * std::max(1.0, std::abs(row[k].get<double>())));
  }
}

}  // namespace
