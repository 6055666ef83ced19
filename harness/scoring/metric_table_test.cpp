// The one metric table (harness/results/metric_table.h) against what the scorers really write: a
// key a scorer writes with no row in the table, or a row no scorer writes, fails here, so a metric
// cannot go missing from the CSV, JSON, SQLite, tune or the report by being added in one place.
#include "harness/results/metric_table.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "harness/results/result_row.h"
#include "harness/scoring/bent_metrics.h"
#include "harness/scoring/metrics.h"
#include "harness/scoring/temporal.h"

namespace aoeval {
namespace {

std::vector<std::string> keys_in_order(const nlohmann::json& object) {
  std::vector<std::string> keys;
  for (auto it = object.begin(); it != object.end(); ++it) keys.push_back(it.key());
  return keys;
}

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// What each scorer writes, from a real scoring of small images (not from a list of names).
nlohmann::json scored_image_keys() {
  const std::vector<float> ref = {0.2f, 0.4f, 0.6f, 0.8f}, est = {0.25f, 0.4f, 0.5f, 0.9f};
  const Metrics m = compare_images({2, 2, ref.data()}, {2, 2, est.data()}, {}, {});
  return to_json(m);
}

nlohmann::json scored_bent_keys() {
  const std::vector<glm::vec3> ref(4, glm::vec3(0, 0, 1)), est(4, glm::vec3(0, 0.1f, 1));
  const auto m = compare_bent(2, 2, ref, est, {}, {});
  nlohmann::json out = nlohmann::json::object();
  add_bent_json(*m, out);
  return out;
}

nlohmann::json scored_sequence_keys() {
  TemporalScorer s;
  std::vector<float> est(4, 0.5f), ref(4, 0.6f), se(4, 0.01f);
  std::vector<uint8_t> compared(4, 1);
  for (int k = 0; k < 3; ++k) {
    TemporalFrame f;
    f.width = f.height = 2;
    f.est = est.data();
    f.ref = ref.data();
    f.ref_stderr = se.data();
    f.compared = compared.data();
    s.add_frame(f);
  }
  return s.scores();
}

TEST(MetricTable, EveryScoredKeyHasARowAndEveryRowIsScored) {
  // The image scorer's JSON, in the table's order (the CSV's column order).
  EXPECT_EQ(keys_in_order(scored_image_keys()).size(), metric_keys_of(MetricFamily::image).size());
  EXPECT_EQ(sorted(keys_in_order(scored_image_keys())),
            sorted(metric_keys_of(MetricFamily::image)));
  EXPECT_EQ(sorted(keys_in_order(scored_bent_keys())), sorted(metric_keys_of(MetricFamily::bent)));
  EXPECT_EQ(sorted(keys_in_order(scored_sequence_keys())),
            sorted(metric_keys_of(MetricFamily::sequence)));
  // The scorers' own key lists are the table's.
  EXPECT_EQ(metric_keys(), metric_keys_of(MetricFamily::image));
  EXPECT_EQ(bent_metric_keys(), metric_keys_of(MetricFamily::bent));
  EXPECT_EQ(TemporalScorer::keys(), metric_keys_of(MetricFamily::sequence));
}

TEST(MetricTable, EveryRowIsAColumnTwiceAndDefined) {
  std::set<std::string> columns;
  for (const auto& c : measured_columns()) EXPECT_TRUE(columns.insert(c).second) << c;
  std::set<std::string> keys;
  for (const MetricDef& m : metric_table()) {
    EXPECT_TRUE(keys.insert(m.key).second) << "twice in the table: " << m.key;
    EXPECT_TRUE(columns.count(m.key)) << m.key << " has no column";
    EXPECT_TRUE(columns.count("true_" + m.key)) << "true_" << m.key << " has no column";
    EXPECT_GE(m.meaning.size(), 10u) << m.key << " has no meaning";
    EXPECT_EQ(find_metric(m.key), &m);
    EXPECT_EQ(find_metric("true_" + m.key), &m);
    // A report column or a dashboard check is of an error measure or the signed bias.
    if (m.dashboard && m.better == Better::none) {
      EXPECT_EQ(m.key, "bias");
    }
  }
  EXPECT_EQ(find_metric("median"), nullptr);
  // Families come in column order: image, then bent, then sequence.
  int last = 0;
  for (const MetricDef& m : metric_table()) {
    EXPECT_GE(static_cast<int>(m.family), last) << m.key;
    last = static_cast<int>(m.family);
  }
}

TEST(MetricTable, ObjectivesAreTheErrorMeasures) {
  const auto objectives = objective_metric_keys();
  for (const char* k :
       {"pixels", "bias", "ref_stderr_rms", "bent_pixels", "bent_ref_stderr", "seq_frames",
        "seq_reference_frames"})
    EXPECT_EQ(std::count(objectives.begin(), objectives.end(), k), 0) << k;
  for (const char* k : {"rmse", "rmse_excess", "ssim", "psnr", "steady_rmse_excess"})
    EXPECT_EQ(std::count(objectives.begin(), objectives.end(), k), 1) << k;
  EXPECT_EQ(find_metric("ssim")->better, Better::higher);
  EXPECT_EQ(find_metric("psnr")->better, Better::higher);
  EXPECT_EQ(find_metric("rmse")->better, Better::lower);
}

}  // namespace
}  // namespace aoeval
