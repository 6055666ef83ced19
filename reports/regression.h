// Regression rules of `aoeval dashboard` (issue #7): when does a change between a baseline row and
// a new row of the same (estimator, parameters, scene, view, resolution) count as a regression?
// A change counts only when it is larger than the noise that the rows themselves say they carry
// and larger than a configured threshold:
//   accuracy  rmse_excess rises by more than max(relative * baseline, sigmas * sigma, absolute),
//             sigma the standard deviation of the change that the reference's Monte-Carlo noise
//             alone would cause (accuracy_sigma below derives it);
//   bias      |bias| rises by more than max(relative * |baseline|, sigmas * sigma, absolute);
//   bent      bent_angle_excess (rows with bent normals) rises by more than max(relative *
//             baseline, sigmas * sigma, absolute), sigma from the reference bent normal's noise;
//   timing    a one-sided Mann-Whitney rank test over the timed repetitions says "slower" at level
//             alpha AND the median time rose by more than `relative`;
//   others    every other key the metric table flags for the dashboard (the CONTRACT §10 sequence
//             keys: seq_rmse_excess, steady_rmse_excess, temporal_rmse_excess, converge_frames,
//             disocclusion_rmse_excess, and any key flagged later) worsens, in the key's direction,
//             by more than max(relative * baseline, sigmas * sigma, absolute) of its MetricRule;
//             sigma from metric_noise_sigma() (0 where the key has no noise model). A key absent
//             from either row (a still view, a column an older run lacks) is not judged.
// Every function here is pure: rows and numbers in, verdicts out (reports/dashboard.* does I/O).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base/mann_whitney.h"
#include "harness/results/result_row.h"

namespace aoeval {

// The thresholds of one tracked key beyond rmse_excess, |bias| and bent_angle_excess: a change
// counts when it exceeds max(relative * |baseline|, sigmas * sigma, absolute).
struct MetricRule {
  double relative = 0.10, sigmas = 3.0, absolute = 0.002;
};
// The built-in rules of the sequence keys (regression.cpp says why each), by key.
std::map<std::string, MetricRule> default_metric_rules();

// Thresholds of one (estimator, scene); reports/regression_config.h reads them from JSON.
struct Thresholds {
  double rmse_excess_relative = 0.05;  // fraction of the baseline's rmse_excess
  double rmse_excess_sigmas = 3.0;     // multiples of the change's noise sigma
  double rmse_excess_absolute = 1e-4;  // AO units: float and driver round-off floor
  // |bias| catches a uniform darkening that rmse_excess may hide behind other errors; the floor is
  // about one 8-bit grey level (1/255 ~ 0.004), below which nobody sees a shift.
  double bias_relative = 0.10;
  double bias_sigmas = 3.0;
  double bias_absolute = 0.005;
  // bent_angle_excess (degrees, bent_metrics.h), for rows with bent normals; the floor is far
  // below what shading shows and above float round-off of unit vectors.
  double bent_relative = 0.05;
  double bent_sigmas = 3.0;
  double bent_absolute = 0.01;
  double time_relative = 0.10;  // median time may grow by this fraction
  double time_alpha = 0.01;     // one-sided rank-test level
  bool missing_fails = true;  // a row ok in the baseline, now skipped or absent: failure or warning
  // Changes (CONTRACT §12, reports/image_change.h): an estimate whose mean AO moved by more than
  // this against the baseline's estimate (and by more than its noise) is CHANGED; about one 8-bit
  // grey level in five, below what a viewer sees but well above float round-off. change_fails:
  // `"change_action": "fail"` makes a change exit 1 like a regression (default "warn").
  double change_mean_shift = 0.005;
  bool change_fails = false;
  // The other tracked keys (config keys "<key>_relative", "<key>_sigmas", "<key>_absolute"); a
  // flagged key without an entry takes MetricRule's defaults.
  std::map<std::string, MetricRule> metrics = default_metric_rules();
  MetricRule rule(const std::string& key) const;
};

// The metric-table keys the dashboard judges through a MetricRule: every key flagged `dashboard`
// except rmse_excess, bias and bent_angle_excess (their own fields above), in column order.
std::vector<std::string> rule_metric_keys();

// ---------------------------------------------------------------- accuracy noise

// What accuracy_sigma needs from a row (its matched-reference metrics).
struct AccuracySample {
  double rmse_excess = 0.0;     // D: the estimate's error with the reference noise removed
  double ref_stderr_rms = 0.0;  // s: rms of the reference's per-pixel standard error
  double bias = 0.0;
  double pixels = 0.0;  // N: compared pixels
  // The row's own rmse_excess_sd (scoring/metrics.h: from every pixel's error and stderr), used
  // instead of the rule from s and N where present; < 0 for rows written before it.
  double rmse_excess_sd = -1.0;
};
std::optional<AccuracySample> accuracy_sample(const ResultRow& row);  // none if a metric is absent

// Standard deviation of the change of rmse_excess (and of bias) between two rows that is due to
// the references' Monte-Carlo noise (derivation in regression.cpp).
//   independent references: sqrt(sigma(D_before)^2 + sigma(D_after)^2);
//   the identical reference (same_reference): the noise is the same draw on both sides and
//   cancels except for a cross term 2 s delta / (sqrt(N) (D_before + D_after)), delta = rms of
//   (after - before) estimate over compared pixels; when delta is unknown (images not kept) the
//   independent-reference sigma is used.
struct AccuracyNoise {
  double rmse_excess_sigma = 0.0, bias_sigma = 0.0;
  std::string model;  // one line: which of the cases above, for the page
};
AccuracyNoise accuracy_noise(const AccuracySample& before, const AccuracySample& after,
                             bool same_reference, std::optional<double> delta_rms);
// sigma of one row's rmse_excess from reference noise alone.
double rmse_excess_sigma(const AccuracySample& s);

// sigma of one row's bent_angle_excess from the reference bent normal's noise alone: D =
// bent_angle_excess, s = bent_ref_stderr, N = bent_pixels (derivation in regression.cpp);
// 0 when a row lacks them.
double bent_excess_sigma(double excess, double ref_stderr, double pixels);

// sigma of one row's value of a rule key from the reference's noise alone (derivation in
// regression.cpp): the sequence rms keys through rmse_excess_sigma with the pixels of every frame
// they pool; 0 for keys without a noise model (counts of frames, disocclusion_rmse_excess whose
// pixel count the row does not carry).
double metric_noise_sigma(const std::string& key, const ResultRow& row);

// True when both rows were scored against the same reference image: same scene, view,
// resolution, AO definition, reference settings (spp, sampler, seed), pixel count and a
// bit-identical ref_stderr_rms (a fingerprint of the reference image itself).
bool same_reference(const ResultRow& before, const ResultRow& after);

// ---------------------------------------------------------------- verdicts

enum class Verdict { regressed, warning, improved, unchanged, not_compared };
const char* to_string(Verdict v);

// One tracked figure of one row pair.
struct Check {
  std::string figure;  // "rmse_excess", "|bias|", "time_ms_median", "status"
  Verdict verdict = Verdict::not_compared;
  double before = 0.0, after = 0.0;
  double threshold = 0.0;  // the change that had to be exceeded
  std::string detail;      // one line: why (sigma, p-value, the rule that decided)
};

// Compares one matched pair. `delta_rms`: rms of (after - before) AO over pixels compared in both,
// when both estimate images could be read. `shift_sigma`: the noise sigma of mean(after - before)
// from the estimator's own randomness (image_change.h's sigma_mean; 0 for a deterministic or
// same-seed pair), added to the bias's: the change of bias is that mean shift plus reference noise.
std::vector<Check> compare_rows(const ResultRow& before, const ResultRow& after,
                                const Thresholds& t, std::optional<double> delta_rms,
                                double shift_sigma = 0.0);
// A row present and ok in the baseline but skipped or absent now.
Check missing_check(const ResultRow* after, const Thresholds& t);
// The worst verdict of a list (regressed > warning > improved > unchanged > not_compared).
Verdict worst(const std::vector<Check>& checks);

}  // namespace aoeval
