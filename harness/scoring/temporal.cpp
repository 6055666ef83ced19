#include "harness/scoring/temporal.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/errors.h"
#include "harness/results/metric_table.h"
#include "harness/scoring/metrics.h"
#include "scenes/bilinear_taps.h"

namespace aoeval {

double TemporalScorer::Sums::excess() const {
  return n > 0.0 ? std::sqrt(std::max(0.0, (err2 - noise) / n)) : 0.0;
}

double TemporalScorer::Sums::variance() const {
  return n > 0.0 ? (4.0 * std::max(0.0, cross) + 2.0 * noise2) / (n * n) : 0.0;
}

TemporalScorer::SharedRun TemporalScorer::current_run() const {
  SharedRun run{run_first_, run_frames_, 0.0};
  double cross = 0.0, noise2 = 0.0, pixels = 0.0;
  for (size_t p = 0; p < run_count_.size(); ++p) {
    if (run_count_[p] != run_frames_ || run_frames_ == 0) continue;  // compared in every frame
    const double mean_err = run_err_[p] / run_frames_, var = run_var_[p];
    cross += (mean_err * mean_err - var) * var;
    noise2 += var * var;
    pixels += 1.0;
  }
  if (pixels > 0.0) run.variance = (4.0 * std::max(0.0, cross) + 2.0 * noise2) / (pixels * pixels);
  return run;
}

double TemporalScorer::frames_sd(int from, double excess) const {
  const int frames = static_cast<int>(frame_excess_.size());
  if (frames <= from) return 0.0;
  double variance = 0.0;
  auto add = [&](const SharedRun& r) {
    const double in_range =
        std::max(0, std::min(r.first + r.frames, frames) - std::max(r.first, from));
    variance += in_range * in_range * r.variance;
  };
  for (const SharedRun& r : runs_) add(r);
  add(current_run());
  const double count = frames - from;
  return excess_sd(excess, variance / (count * count));
}

const std::vector<std::string>& TemporalScorer::keys() {
  static const std::vector<std::string> k = metric_keys_of(MetricFamily::sequence);
  return k;
}

double TemporalScorer::add_frame(const TemporalFrame& f) {
  const int k = static_cast<int>(frame_excess_.size());
  if (k == 0) {
    width_ = f.width;
    height_ = f.height;
    flicker_px_.assign(static_cast<size_t>(width_) * height_, Sums{});
    lag_px_.assign(flicker_px_.size(), Sums{});
  } else if (f.width != width_ || f.height != height_) {
    throw InputError("sequence frame " + std::to_string(k) + " is " + std::to_string(f.width) +
                     "x" + std::to_string(f.height) + ", frame 0 was " + std::to_string(width_) +
                     "x" + std::to_string(height_));
  }
  const size_t n = static_cast<size_t>(width_) * height_;
  if (k == 0 || !f.ref_repeats_previous) {  // a reference of its own: a new run
    if (run_frames_ > 0) runs_.push_back(current_run());
    run_err_.assign(n, 0.0);
    run_var_.assign(n, 0.0f);
    run_count_.assign(n, 0);
    run_first_ = k;
    run_frames_ = 0;
  }
  ++run_frames_;
  Sums frame;
  std::vector<int> age(n, -1), run(n, 0);
  // This frame's pair differences d, for the next frame's covariance term (NaN: none).
  std::vector<double> pair_d(n, std::numeric_limits<double>::quiet_NaN());
  if (prev_pair_d_.size() != n) prev_pair_d_ = pair_d;
  // by_age_'s entries by age (ages here are at most k): a map lookup per pixel was a fifth of this
  // function's time; std::map's entries do not move, and each is added to in pixel order as before.
  std::vector<Sums*> of_age(static_cast<size_t>(k) + 1, nullptr);
  Kept now;
  now.ref.assign(f.ref, f.ref + n);
  now.var.assign(n, 0.0f);
  now.err.assign(n, 0.0);
  now.prev.assign(n, -1);
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      const size_t p = static_cast<size_t>(j) * width_ + i;
      if (!f.compared[p]) continue;
      const double err = static_cast<double>(f.est[p]) - f.ref[p];
      const double var =
          f.ref_stderr ? static_cast<double>(f.ref_stderr[p]) * f.ref_stderr[p] : 0.0;
      now.err[p] = err;
      now.var[p] = static_cast<float>(var);
      frame.n += 1.0;
      frame.err2 += err * err;
      frame.noise += var;
      run_err_[p] += err;
      run_var_[p] = static_cast<float>(var);
      ++run_count_[p];
      const bool disoccluded = f.disoccluded && f.disoccluded[p] > 0.5f;
      if (k == 0) {
        run[p] = 1;
        continue;
      }
      const double mx = f.motion ? f.motion[2 * p] : 0.0, my = f.motion ? f.motion[2 * p + 1] : 0.0;
      // A non-finite offset would read frame k - 1 at an undefined index (read_gbuffer refuses
      // such files; this guards every other caller).
      if (!std::isfinite(mx) || !std::isfinite(my))
        throw InputError("sequence frame " + std::to_string(k) + ": motion at pixel (" +
                         std::to_string(i) + ", " + std::to_string(j) + ") is not finite");
      const double qx = i + 0.5 - mx, qy = j + 0.5 - my;
      if (disoccluded) {
        age[p] = 0;
      } else {
        // The trajectory's step back: the nearest pixel of frame k - 1 (its sample positions are
        // the pixel centres shifted by its jitter).
        const auto a = static_cast<int>(std::floor(qx - f.prev_jitter_x)),
                   b = static_cast<int>(std::floor(qy - f.prev_jitter_y));
        if (a >= 0 && b >= 0 && a < width_ && b < height_) {
          const int q = b * width_ + a;
          now.prev[p] = q;
          const int before = prev_age_[q];
          age[p] = before >= 0 ? before + 1 : -1;
          run[p] = prev_run_[q] + 1;
        } else {
          run[p] = 1;
        }
        const BilinearTaps taps =
            bilinear_taps(qx, qy, width_, height_, [&](int t) { return prev_compared_[t] != 0; });
        if (taps.taps > 0 && taps.total > 1e-9) {
          double est_then = 0.0, ref_then = 0.0, var_then = 0.0;
          for (int t = 0; t < taps.taps; ++t) {
            const double w = taps.weight[t] / taps.total;
            est_then += w * prev_est_[taps.index[t]];
            ref_then += w * prev_ref_[taps.index[t]];
            var_then += w * w * prev_var_[taps.index[t]];
          }
          const double d = (f.est[p] - est_then) - (f.ref[p] - ref_then);
          temporal_.n += 1.0;
          temporal_.err2 += d * d;
          flicker_px_[p].n += 1.0;
          flicker_px_[p].err2 += d * d;
          // An unchanged frame's reference is frame k - 1's (traced once): their difference
          // holds no reference noise, so none is removed (CONTRACT §10's terms are for
          // independent references).
          if (!f.ref_repeats_previous) {
            const double v = var + var_then;
            temporal_.noise += v;
            temporal_.cross += (d * d - v) * v;
            temporal_.noise2 += v * v;
            pair_d[p] = d;
            // The pair before this one along the trajectory shares frame k - 1's reference noise
            // n: Cov(d^2, d_before^2) = -4 delta delta_before se^2 + 2 se^4, and d d_before
            // estimates delta delta_before - se^2 without bias (d = delta - n + ..., d_before =
            // delta_before + n - ...): -4 d d_before se^2 - 2 se^4 per pixel.
            const int q = now.prev[p];
            if (q >= 0 && std::isfinite(prev_pair_d_[q])) {
              const double shared = prev_var_[q];
              temporal_pair_cov_ += -4.0 * d * prev_pair_d_[q] * shared - 2.0 * shared * shared;
            }
          }
        }
      }
      if (age[p] >= 0) {
        Sums*& slot = of_age.at(static_cast<size_t>(age[p]));
        if (!slot) slot = &by_age_[age[p]];
        Sums& s = *slot;
        s.n += 1.0;
        s.err2 += err * err;
        s.noise += var;
      }
    }
  if (frame.n == 0.0)
    throw InputError("sequence frame " + std::to_string(k) +
                     ": no pixel is covered in both images");
  kept_.push_back(std::move(now));
  if (static_cast<int>(kept_.size()) > kSettleAge + 1) kept_.erase(kept_.begin());
  follow_trajectories(age, run);
  frame_excess_.push_back(frame.excess());
  reference_frames_ += k == 0 || !f.ref_repeats_previous;
  prev_est_.assign(f.est, f.est + n);
  prev_ref_.assign(f.ref, f.ref + n);
  prev_var_.assign(n, 0.0f);
  if (f.ref_stderr)
    for (size_t p = 0; p < n; ++p) prev_var_[p] = f.ref_stderr[p] * f.ref_stderr[p];
  prev_compared_.assign(f.compared, f.compared + n);
  prev_age_ = std::move(age);
  prev_run_ = std::move(run);
  prev_pair_d_ = std::move(pair_d);
  return frame_excess_.back();
}

void TemporalScorer::follow_trajectories(const std::vector<int>& age, const std::vector<int>& run) {
  const int last = static_cast<int>(kept_.size()) - 1;  // this frame
  const Kept& now = kept_[last];
  int at[kSettleAge + 1];
  for (size_t p = 0; p < age.size(); ++p) {
    const bool settles = age[p] == kSettleAge, lags = run[p] >= kLagFrames + 1;
    if (!settles && !lags) continue;
    // Trace the trajectory back: at[g] is its pixel in the frame `last - (depth - g)`. Every pixel
    // on the way was compared (an age or a run is only carried through compared pixels).
    const int depth = settles ? kSettleAge : kLagFrames;
    at[depth] = static_cast<int>(p);
    for (int g = depth; g > 0; --g) at[g - 1] = kept_[last - (depth - g)].prev[at[g]];
    if (lags) {
      const Kept& then = kept_[last - kLagFrames];
      const int q = at[depth - kLagFrames];
      const double change = std::abs(static_cast<double>(now.ref[p]) - then.ref[q]);
      if (change > 0.05 + 3.0 * std::sqrt(static_cast<double>(now.var[p]) + then.var[q])) {
        lag_.n += 1.0;
        lag_.err2 += now.err[p] * now.err[p];
        lag_.noise += now.var[p];
        lag_px_[p].n += 1.0;
        lag_px_[p].err2 += now.err[p] * now.err[p];
        lag_px_[p].noise += now.var[p];
      }
    }
    if (!settles) continue;
    bool still = true;
    for (int g = 0; g < kSettleAge && still; ++g) {
      const Kept& then = kept_[last - (kSettleAge - g)];
      const double change = std::abs(static_cast<double>(now.ref[p]) - then.ref[at[g]]);
      still = change <= 0.02 + 3.0 * std::sqrt(static_cast<double>(now.var[p]) + then.var[at[g]]);
    }
    if (!still) continue;
    for (int g = 0; g <= kSettleAge; ++g) {
      const Kept& then = kept_[last - (kSettleAge - g)];
      const double e = then.err[at[g]];
      settle_[g].n += 1.0;
      settle_[g].err2 += e * e;
      settle_[g].noise += then.var[at[g]];
    }
  }
}

namespace {

template <class Sums>
std::vector<float> map_of(const std::vector<Sums>& px) {
  std::vector<float> out(px.size(), std::nanf(""));
  for (size_t p = 0; p < px.size(); ++p)
    if (px[p].n > 0.0) out[p] = static_cast<float>(px[p].excess());
  return out;
}

}  // namespace

// The flicker map's sums hold no noise: excess() is the rms of d there.
std::vector<float> TemporalScorer::flicker_map() const {
  return map_of(flicker_px_);
}
std::vector<float> TemporalScorer::lag_map() const {
  return map_of(lag_px_);
}

std::map<int, double> TemporalScorer::settle_excess_by_age() const {
  std::map<int, double> out;
  if (settle_[0].n > 0.0)
    for (int g = 0; g <= kSettleAge; ++g) out[g] = settle_[g].excess();
  return out;
}

std::map<int, double> TemporalScorer::rmse_excess_by_age() const {
  std::map<int, double> out;
  for (const auto& [age, sums] : by_age_) out[age] = sums.excess();
  return out;
}

nlohmann::json TemporalScorer::scores(const std::string& prefix) const {
  nlohmann::json out = nlohmann::json::object();
  const int frames = static_cast<int>(frame_excess_.size());
  auto rms = [&](int from) {
    double s = 0.0;
    for (int k = from; k < frames; ++k) s += frame_excess_[k] * frame_excess_[k];
    return frames > from ? std::sqrt(s / (frames - from)) : 0.0;
  };
  const double steady = rms(frames / 2);
  out[prefix + "seq_frames"] = frames;
  out[prefix + "seq_reference_frames"] = reference_frames_;
  out[prefix + "seq_rmse_excess"] = rms(0);
  out[prefix + "seq_rmse_excess_sd"] = frames_sd(0, rms(0));
  out[prefix + "steady_rmse_excess"] = steady;
  out[prefix + "steady_rmse_excess_sd"] = frames_sd(frames / 2, steady);
  out[prefix + "temporal_rmse"] =
      temporal_.n > 0.0 ? nlohmann::json(std::sqrt(temporal_.err2 / temporal_.n)) : nullptr;
  out[prefix + "temporal_rmse_excess"] =
      temporal_.n > 0.0 ? nlohmann::json(temporal_.excess()) : nullptr;
  // Neighbouring pairs share a frame's reference: their covariances enter twice.
  const double temporal_variance =
      temporal_.n > 0.0 ? std::max(0.0, temporal_.variance() +
                                            2.0 * temporal_pair_cov_ / (temporal_.n * temporal_.n))
                        : 0.0;
  out[prefix + "temporal_rmse_excess_sd"] =
      temporal_.n > 0.0 ? nlohmann::json(excess_sd(temporal_.excess(), temporal_variance))
                        : nullptr;
  int converge = frames;
  for (int k = frames - 1; k >= 0 && frame_excess_[k] <= 1.1 * steady; --k) converge = k;
  out[prefix + "converge_frames"] = converge;
  nlohmann::json settle = nullptr;
  if (settle_[0].n > 0.0) {
    Sums pooled;
    for (int g = 9; g <= kSettleAge; ++g) pooled.add(settle_[g]);
    settle = 9;
    for (int g = 0; g <= 8; ++g)
      if (settle_[g].excess() <= 1.1 * pooled.excess()) {
        settle = g;
        break;
      }
  }
  out[prefix + "settle_frames"] = settle;
  Sums recent;
  for (const auto& [age, sums] : by_age_)
    if (age <= 3) recent.add(sums);
  out[prefix + "disocclusion_rmse_excess"] =
      recent.n > 0.0 ? nlohmann::json(recent.excess()) : nullptr;
  out[prefix + "lag_rmse_excess"] = lag_.n > 0.0 ? nlohmann::json(lag_.excess()) : nullptr;
  return out;
}

}  // namespace aoeval
