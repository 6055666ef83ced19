// Regression rules (see regression.h).
//
// Accuracy noise. Per compared pixel i let t_i be the true AO, r_i = t_i + n_i the reference with
// Monte-Carlo noise n_i (mean 0, variance sigma_i^2, independent across pixels: every pixel has
// its own randomisation, references/samplers.h), e_i the estimate and d_i = e_i - t_i its error.
// CONTRACT §4: rmse^2 = (1/N) sum (d_i - n_i)^2 and rmse_excess^2 = rmse^2 - (1/N) sum sigma_i^2,
// an unbiased estimate of D^2 = (1/N) sum d_i^2. Taking n_i Gaussian (E n^4 = 3 sigma^4):
//   Var(rmse_excess^2) = (1/N^2) sum Var((d_i - n_i)^2) = (1/N^2) sum (4 d_i^2 sigma_i^2 + 2
//   sigma_i^4)
//                      ~= (4 D^2 s^2 + 2 s^4) / N,     s = ref_stderr_rms, N = pixels.
// Replacing sigma_i by their rms assumes the error does not concentrate where the reference is
// noisiest, and it does: in creases both are large, and a bounded definition's open pixels have
// neither (sum d_i^2 sigma_i^2 measured up to 4.9 x D^2 s^2 N on the default suite's views, so
// this rule's sigma was up to 2.2 x too small there). A row therefore carries its own
// rmse_excess_sd, the first line's sum taken per pixel at scoring time (scoring/metrics.h), and
// the sequence keys theirs (scoring/temporal.h); the rule below is the fallback for rows written
// before those keys. The delta method, sigma(D) = sigma(D^2) / (2 D), gives
//   sigma(D) = s sqrt(D^2 + s^2 / 2) / (D sqrt(N)),
// which diverges as D -> 0; there D^2 itself has sigma s^2 sqrt(2/N), so D is known to within
// s (2/N)^(1/4). rmse_excess_sigma() takes the smaller of the two. Two runs scored against
// independent references add variances.
// The same reference on both sides (a cached reference: same content, same draw n_i): the change
//   D_a^2 - D_b^2 = (1/N) sum (d'_i^2 - d_i^2) - (2/N) sum n_i (d'_i - d_i)
// has reference noise only in the second term, variance (4/N^2) sum sigma_i^2 (e'_i - e_i)^2
// ~= 4 s^2 delta^2 / N with delta the rms of the estimates' difference; and since
// D_a^2 - D_b^2 = (D_a - D_b)(D_a + D_b), sigma(D_a - D_b) = 2 s delta / (sqrt(N) (D_a + D_b)).
// An unchanged deterministic estimator (delta = 0) therefore has exactly zero noise, and what is
// left is the absolute floor for round-off. Bias: (1/N) sum (e_i - r_i) has reference noise of
// variance s^2 / N per run, independent references add; with the same reference it cancels
// exactly (bias_a - bias_b = mean(e' - e)).
// Bent normals (bent_metrics.h): per pixel the squared angle |e_i - n_i|^2, with n_i the
// reference's angular error, a 2-D vector across the bent normal of total variance sigma_i^2
// (bent_stderr^2; Gaussian, so |n|^2 has variance sigma^4) independent of the estimate's error e_i.
// Var(|e - n|^2) = 4 Var(e . n) + Var(|n|^2) = 2 |e|^2 sigma^2 + sigma^4, hence
//   Var(D^2) ~= (2 D^2 s^2 + s^4) / N,   sigma(D) = s sqrt(2 D^2 + s^2) / (2 D sqrt(N)),
// and near D = 0, D^2 has sigma s^2 / sqrt(N): D is known to within s N^(-1/4); the smaller of
// the two is used, and two rows add variances (the independent-reference model throughout:
// conservative when both rows share one reference).
// An estimator's own randomness across seeds enters the bias check only, as compare_rows'
// shift_sigma, measured from the two estimate images (image_change.h); rmse_excess does not model
// it (deterministic estimators repeat bit for bit, CONTRACT "same seed, same bits").
// Sequence keys (CONTRACT §10). seq_rmse_excess^2 is the mean over F frames of each frame's
// rmse_excess^2, each frame scored against its own reference (independent noise per frame), so
// its square is an average of F estimates of the kind above over N pixels each: the same formula
// with N -> N F (steady_rmse_excess: the last F/2 frames, N F/2). temporal_rmse_excess^2 removes
// mean(stderr_k^2 + stderr_{k-1}^2) ~= 2 s^2 from temporal_rmse^2 over the F - 1 frame pairs: the
// formula with s -> sqrt(2) s and N -> N (F - 1) (neighbouring pairs share a frame, so this is
// optimistic by up to sqrt(2), which the relative threshold covers). N is the last frame's
// `pixels`, F is `seq_reference_frames` (the frames with a reference of their own: 1 for a static
// camera over a static scene, whose frames share one; `seq_frames` in rows written before it).
// disocclusion_rmse_excess pools a pixel count the row does not carry, and frame counts are
// integers: they have no sigma, only their relative and absolute floors.
#include "reports/regression.h"

#include "base/summary.h"
#include "base/welch_log_t.h"
#include "harness/results/machine_class.h"
#include "harness/results/metric_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace aoeval {

namespace {

template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char text[320];
  std::snprintf(text, sizeof text, fmt, args...);
  return text;
}

double metric(const nlohmann::json& metrics, const char* key, bool* ok) {
  const auto it = metrics.find(key);
  if (it == metrics.end() || !it->is_number()) {
    *ok = false;
    return 0.0;
  }
  return it->get<double>();
}

// The usual shape of a threshold check: a rise of `after - before` beyond max(rel * |before|,
// k * sigma, absolute) regresses, the same fall improves.
Check threshold_check(const std::string& figure, double before, double after, double relative,
                      double sigmas, double sigma, double absolute, const std::string& noise) {
  Check c;
  c.figure = figure;
  c.before = before;
  c.after = after;
  c.threshold = std::max({relative * std::abs(before), sigmas * sigma, absolute});
  const double change = after - before;
  c.verdict = change > c.threshold    ? Verdict::regressed
              : -change > c.threshold ? Verdict::improved
                                      : Verdict::unchanged;
  c.detail = format(
                 "change %+.3g, threshold %.3g = max(%g%% of baseline, %g sigma = %.3g, "
                 "floor %g); ",
                 change, c.threshold, relative * 100, sigmas, sigmas * sigma, absolute) +
             noise;
  return c;
}

}  // namespace

std::map<std::string, MetricRule> default_metric_rules() {
  // The rms errors over frames: as rmse_excess (5 % and its sigma) with the floor of one frame's
  // round-off. Flicker and disocclusion are smaller numbers measured over fewer samples: 10 %.
  // Frame counts: two frames or a quarter, whichever is more (one frame is their resolution).
  // A key a row lacks (a still view's sequence keys, a blank lag or settle) is never judged.
  return {{"seq_rmse_excess", {.relative = 0.05, .sigmas = 3.0, .absolute = 1e-4}},
          {"steady_rmse_excess", {.relative = 0.05, .sigmas = 3.0, .absolute = 1e-4}},
          {"temporal_rmse_excess", {.relative = 0.10, .sigmas = 3.0, .absolute = 2e-4}},
          {"disocclusion_rmse_excess", {.relative = 0.10, .sigmas = 3.0, .absolute = 0.002}},
          {"lag_rmse_excess", {.relative = 0.10, .sigmas = 3.0, .absolute = 0.002}},
          {"converge_frames", {.relative = 0.25, .sigmas = 3.0, .absolute = 2.0}},
          {"settle_frames", {.relative = 0.25, .sigmas = 3.0, .absolute = 2.0}}};
}

MetricRule Thresholds::rule(const std::string& key) const {
  const auto it = metrics.find(key);
  return it == metrics.end() ? MetricRule{} : it->second;
}

std::vector<std::string> rule_metric_keys() {
  std::vector<std::string> keys;
  for (const std::string& k : dashboard_metric_keys())
    if (k != "rmse_excess" && k != "bias" && k != "bent_angle_excess") keys.push_back(k);
  return keys;
}

double metric_noise_sigma(const std::string& key, const ResultRow& row) {
  const auto sample = accuracy_sample(row);
  bool ok = true;
  const double value = metric(row.metrics, key.c_str(), &ok);
  const double frames = metric(row.metrics, "seq_frames", &ok);
  if (!sample || !ok || frames < 1.0) return 0.0;
  // The independent reference images the key pools: a frame that repeats frame k - 1's reference
  // (a static camera over a static scene, traced once) adds no noise of its own. Rows written
  // before seq_reference_frames existed traced every frame.
  bool counted = true;
  const double traced = metric(row.metrics, "seq_reference_frames", &counted);
  const double references = counted && traced >= 1.0 ? std::min(traced, frames) : frames;
  AccuracySample s = *sample;
  s.rmse_excess = value;
  bool measured = true;  // the row's own sd of this key, from every pixel of every frame
  const double sd = metric(row.metrics, (key + "_sd").c_str(), &measured);
  if (measured &&
      (key == "seq_rmse_excess" || key == "steady_rmse_excess" || key == "temporal_rmse_excess"))
    return std::max(0.0, sd);
  if (key == "seq_rmse_excess") {
    s.pixels *= references;
  } else if (key == "steady_rmse_excess") {
    s.pixels *= std::max(1.0, std::floor(references / 2.0));
  } else if (key == "temporal_rmse_excess" && references >= 2.0) {
    s.pixels *= references - 1.0;
    s.ref_stderr_rms *= std::sqrt(2.0);
  } else {
    return 0.0;  // temporal_rmse_excess over one reference: frame differences hold no ref noise
  }
  return rmse_excess_sigma(s);
}

std::optional<AccuracySample> accuracy_sample(const ResultRow& row) {
  bool ok = true;
  AccuracySample s;
  s.rmse_excess = metric(row.metrics, "rmse_excess", &ok);
  s.ref_stderr_rms = metric(row.metrics, "ref_stderr_rms", &ok);
  s.bias = metric(row.metrics, "bias", &ok);
  s.pixels = metric(row.metrics, "pixels", &ok);
  if (!ok) return std::nullopt;
  bool measured = true;
  const double sd = metric(row.metrics, "rmse_excess_sd", &measured);
  if (measured) s.rmse_excess_sd = std::max(0.0, sd);
  return s;
}

double rmse_excess_sigma(const AccuracySample& a) {
  if (a.rmse_excess_sd >= 0.0) return a.rmse_excess_sd;
  const double s = a.ref_stderr_rms, n = a.pixels, d = a.rmse_excess;
  if (n <= 0.0 || s <= 0.0) return 0.0;
  const double near_zero = s * std::pow(2.0 / n, 0.25);
  if (d <= 0.0) return near_zero;
  return std::min(near_zero, s * std::sqrt(d * d + 0.5 * s * s) / (d * std::sqrt(n)));
}

AccuracyNoise accuracy_noise(const AccuracySample& b, const AccuracySample& a, bool same_ref,
                             std::optional<double> delta_rms) {
  AccuracyNoise noise;
  if (same_ref) {
    noise.bias_sigma = 0.0;  // bias_a - bias_b = mean(e' - e): the reference cancels
    if (delta_rms) {
      const double sum = b.rmse_excess + a.rmse_excess;
      noise.rmse_excess_sigma = sum > 0.0 && b.pixels > 0.0 ? 2.0 * b.ref_stderr_rms * *delta_rms /
                                                                  (std::sqrt(b.pixels) * sum)
                                                            : 0.0;
      noise.model = format("same reference on both sides; rms(new - baseline) = %.3g", *delta_rms);
      return noise;
    }
    noise.model = "same reference, estimate images unavailable: independent-reference sigma";
  } else {
    noise.model = "independent references: variances add";
    const double vb = b.pixels > 0 ? b.ref_stderr_rms * b.ref_stderr_rms / b.pixels : 0.0;
    const double va = a.pixels > 0 ? a.ref_stderr_rms * a.ref_stderr_rms / a.pixels : 0.0;
    noise.bias_sigma = std::sqrt(vb + va);
  }
  noise.rmse_excess_sigma = std::hypot(rmse_excess_sigma(b), rmse_excess_sigma(a));
  return noise;
}

double bent_excess_sigma(double d, double s, double n) {
  if (n <= 0.0 || s <= 0.0) return 0.0;
  const double near_zero = s * std::pow(n, -0.25);
  if (d <= 0.0) return near_zero;
  return std::min(near_zero, s * std::sqrt(2.0 * d * d + s * s) / (2.0 * d * std::sqrt(n)));
}

bool same_reference(const ResultRow& b, const ResultRow& a) {
  if (b.scene != a.scene || b.view != a.view || b.width != a.width || b.height != a.height ||
      b.definition != a.definition || b.reference != a.reference)
    return false;
  const auto sb = accuracy_sample(b), sa = accuracy_sample(a);
  return sb && sa && sb->pixels == sa->pixels && sb->ref_stderr_rms == sa->ref_stderr_rms;
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::regressed:
      return "regressed";
    case Verdict::warning:
      return "warning";
    case Verdict::improved:
      return "improved";
    case Verdict::unchanged:
      return "unchanged";
    case Verdict::not_compared:
      return "not compared";
  }
  return "?";
}

std::vector<Check> compare_rows(const ResultRow& before, const ResultRow& after,
                                const Thresholds& t, std::optional<double> delta_rms,
                                double shift_sigma) {
  std::vector<Check> checks;
  const auto sb = accuracy_sample(before), sa = accuracy_sample(after);
  if (sb && sa) {
    const bool same = same_reference(before, after);
    const AccuracyNoise noise = accuracy_noise(*sb, *sa, same, delta_rms);
    checks.push_back(threshold_check("rmse_excess", sb->rmse_excess, sa->rmse_excess,
                                     t.rmse_excess_relative, t.rmse_excess_sigmas,
                                     noise.rmse_excess_sigma, t.rmse_excess_absolute, noise.model));
    checks.push_back(threshold_check(
        "|bias|", std::abs(sb->bias), std::abs(sa->bias), t.bias_relative, t.bias_sigmas,
        std::hypot(noise.bias_sigma, shift_sigma), t.bias_absolute,
        noise.model + (shift_sigma > 0.0 ? format("; estimator noise sigma %.3g", shift_sigma)
                                         : std::string())));
  } else {
    Check c;
    c.figure = "rmse_excess";
    c.detail = "a row lacks rmse_excess, ref_stderr_rms, bias or pixels";
    checks.push_back(c);
  }

  // Bent normals, where both rows carry them (bent_metrics.h); absent otherwise.
  {
    bool ok = true;
    const double db = metric(before.metrics, "bent_angle_excess", &ok),
                 da = metric(after.metrics, "bent_angle_excess", &ok),
                 noise_b = metric(before.metrics, "bent_ref_stderr", &ok),
                 noise_a = metric(after.metrics, "bent_ref_stderr", &ok),
                 nb = metric(before.metrics, "bent_pixels", &ok),
                 na = metric(after.metrics, "bent_pixels", &ok);
    if (ok) {
      const double sigma =
          std::hypot(bent_excess_sigma(db, noise_b, nb), bent_excess_sigma(da, noise_a, na));
      checks.push_back(threshold_check("bent_angle_excess", db, da, t.bent_relative, t.bent_sigmas,
                                       sigma, t.bent_absolute,
                                       "reference bent-normal noise, independent references"));
    }
  }

  // Every other key the metric table flags (the sequence keys), where both rows carry it.
  for (const std::string& key : rule_metric_keys()) {
    bool ok = true;
    const double b = metric(before.metrics, key.c_str(), &ok),
                 a = metric(after.metrics, key.c_str(), &ok);
    if (!ok) continue;
    const MetricRule rule = t.rule(key);
    const double sigma =
        std::hypot(metric_noise_sigma(key, before), metric_noise_sigma(key, after));
    // Higher-is-better keys are judged on their negatives and reported as they are.
    const double sign = find_metric(key)->better == Better::higher ? -1.0 : 1.0;
    Check c =
        threshold_check(key, sign * b, sign * a, rule.relative, rule.sigmas, sigma, rule.absolute,
                        sigma > 0.0 ? "reference noise over the sequence's frames"
                                    : "no noise model: relative and absolute floors");
    c.before = b;
    c.after = a;
    checks.push_back(c);
  }

  Check time;
  time.figure = "time_ms_median";
  time.before = before.time_ms_median;
  time.after = after.time_ms_median;
  time.threshold = t.time_relative * before.time_ms_median;
  const auto& xb = before.time_ms_samples;
  const auto& xa = after.time_ms_samples;
  if (xb.empty() || xa.empty()) {
    time.detail = "no timed repetitions stored";
  } else if (machine_class(before) != machine_class(after)) {
    // Rows merged from several nodes (issue 19): times compare only within a machine class.
    time.detail = "different machine classes (" + machine_class(before) + " vs " +
                  machine_class(after) + "): times compare only within a class";
  } else {
    const RankTest r = mann_whitney(xb, xa);
    const double ratio = median(xa) / median(xb);
    const bool slower = r.p_greater < t.time_alpha && ratio > 1.0 + t.time_relative;
    const bool faster = r.p_less < t.time_alpha && ratio < 1.0 / (1.0 + t.time_relative);
    time.verdict = slower ? Verdict::regressed : faster ? Verdict::improved : Verdict::unchanged;
    time.detail = format(
        "median x%.3f (limit x%.2f); Mann-Whitney U = %g, p(slower) = %.3g, "
        "p(faster) = %.3g, alpha %g, %s, n = %zu vs %zu",
        ratio, 1.0 + t.time_relative, r.u, r.p_greater, r.p_less, t.time_alpha,
        r.exact ? "exact" : "normal approximation", xb.size(), xa.size());
    const double floor_p =
        smallest_one_sided_p(static_cast<int>(xb.size()), static_cast<int>(xa.size()));
    auto positive = [](const std::vector<double>& x) {
      return std::all_of(x.begin(), x.end(), [](double v) { return v > 0.0 && std::isfinite(v); });
    };
    if (floor_p >= t.time_alpha && xb.size() >= 2 && xa.size() >= 2 && positive(xb) &&
        positive(xa)) {
      // No rank outcome could reach alpha (a suite that stops a steady point at 3 repetitions,
      // harness/evaluation/repetition_policy.h): Welch's t on the log times judges instead, at the
      // same alpha and the same ratio limit, and the detail says so (base/welch_log_t.h).
      const LogTTest w = welch_log_t_test(xb, xa);
      const bool w_slower = w.p_greater < t.time_alpha && ratio > 1.0 + t.time_relative;
      const bool w_faster = w.p_less < t.time_alpha && ratio < 1.0 / (1.0 + t.time_relative);
      time.verdict = w_slower   ? Verdict::regressed
                     : w_faster ? Verdict::improved
                                : Verdict::unchanged;
      time.detail += format(
          "; the rank test cannot reach alpha at these counts (smallest p %.3g), so Welch's t on "
          "log times judges: t = %.3g, df = %.3g, p(slower) = %.3g, p(faster) = %.3g",
          floor_p, w.t, w.df, w.p_greater, w.p_less);
    } else if (floor_p >= t.time_alpha) {
      // No test can judge (a side with one repetition, or a time that is not positive): say so
      // rather than pass silently.
      time.verdict = Verdict::not_compared;
      time.detail += xb.size() < 2 || xa.size() < 2
                         ? format("; too few repetitions: the smallest possible p is %.3g", floor_p)
                         : format(
                               "; a time that is not positive: no log-time test, and the "
                               "smallest possible rank p is %.3g",
                               floor_p);
    }
  }
  checks.push_back(time);
  return checks;
}

Check missing_check(const ResultRow* after, const Thresholds& t) {
  Check c;
  c.figure = "status";
  c.verdict = t.missing_fails ? Verdict::regressed : Verdict::warning;
  c.detail = after ? "ok in the baseline, now \"" + after->status + "\""
                   : "ok in the baseline, absent from the new run";
  return c;
}

Verdict worst(const std::vector<Check>& checks) {
  auto rank = [](Verdict v) {
    switch (v) {
      case Verdict::regressed:
        return 4;
      case Verdict::warning:
        return 3;
      case Verdict::improved:
        return 2;
      case Verdict::unchanged:
        return 1;
      case Verdict::not_compared:
        return 0;
    }
    return 0;
  };
  Verdict w = Verdict::not_compared;
  for (const auto& c : checks)
    if (rank(c.verdict) > rank(w)) w = c.verdict;
  return w;
}

}  // namespace aoeval
