// LDR-FLIP (Andersson et al. 2020, see flip.h) for grey images, written from the paper's
// description. Section names follow the paper's §4 ("FLIP"); we cite them by title because we
// did not have the paper at hand to check the numbering. Constants and where they come from:
//   * Viewing condition: 0.7 m from a 0.7 m wide 3840-pixel monitor; pixels per degree
//     ppd = distance * (pixels / width) * pi / 180 = 67.02 (the paper's default observer).
//   * Colour pipeline, "spatial filtering": images go sRGB -> linear RGB (IEC 61966-2-1) -> XYZ
//     (sRGB/D65 matrix) -> YCxCz (Y = 116 Y/Yw - 16, Cx = 500 (X/Xw - Y/Yw), Cz = 200 (Y/Yw -
//     Z/Zw)); each channel is filtered with the spatial CSF approximation
//       s(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
//     x in degrees, with (a1, b1, a2, b2) = (1, 0.0047, 0, 1e-5) achromatic,
//     (1, 0.0053, 0, 1e-5) red-green and (34.1, 0.04, 13.5, 0.025) blue-yellow; the kernel radius
//     is ceil(3 sqrt(max b / (2 pi^2)) ppd) = 10 pixels for every channel, weights sum to 1.
//     The result is taken back to linear RGB and clamped to [0, 1].
//   * "Perceptually uniform colour space": linear RGB -> XYZ -> CIELAB (D65 white), then the Hunt
//     adjustment a* <- 0.01 L* a*, b* <- 0.01 L* b*.
//   * "Colour metric": HyAB distance |dL*| + sqrt(da*^2 + db*^2), raised to qc = 0.7, then
//     re-mapped to [0, 1]: e < pc cmax -> (pt / (pc cmax)) e, else pt + (e - pc cmax) /
//     (cmax - pc cmax) (1 - pt), with pc = 0.4, pt = 0.95 and cmax = HyAB(Hunt(Lab(green)),
//     Hunt(Lab(blue)))^qc, the largest distance between two colours of the gamut (= 41.3).
//   * "Feature pipeline": on the normalised achromatic channel (Y + 16) / 116 = Y/Yw of the
//     *unfiltered* images, edges and points are detected with the first and second partial
//     derivatives of a Gaussian with standard deviation sd = 0.5 w ppd, w = 0.082 degrees (the
//     peak-to-trough width of the human edge detector), radius ceil(3 sd) = 9 pixels; the
//     positive weights of each filter are normalised to sum to 1 and the negative ones to -1.
//     Feature difference dEf = (max(| |edge_ref| - |edge_est| |, | |point_ref| - |point_est| |)
//     / sqrt(2))^qf with qf = 0.5, |.| the norm of the (x, y) filter responses.
//   * "Final error": FLIP = dEc^(1 - dEf).
// Grey input makes the chroma channels vanish: for linear grey RGB (t, t, t) the sRGB matrix gives
// XYZ = t (Xw, 1, Zw) (its rows sum to the D65 white), so Cx = Cz = 0 before and after filtering,
// the filtered colour is grey again, a* = b* = 0, and HyAB reduces to |dL*|. We therefore filter
// only the achromatic channel; since the filter is normalised, filtering Y = 116 t - 16 is the
// same as filtering t and applying the affine map afterwards. CIELAB's f(t) uses the exact CIE
// constants (6/29)^3 and 1 / (3 (6/29)^2) where the authors' code rounds them to 0.008856 and
// 7.787. With every pixel compared, the map agrees with the authors' FLIP v1.0 C++ code to 1e-4
// per pixel (it computes in float); metrics_test.cpp pins values that code printed.
#include "harness/scoring/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "harness/scoring/side_by_side.h"

namespace aoeval {

namespace detail {

namespace {

template <class Fn>
void for_rows(int height, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) fn(y);
  });
}

}  // namespace

void filter_rows(const std::vector<double>& in, int width, int height,
                 const std::vector<double>& kernel, Border border, std::vector<double>& out) {
  const int r = static_cast<int>(kernel.size() / 2);
  out.resize(in.size());
  for_rows(height, [&](int y) {
    const double* src = in.data() + static_cast<size_t>(y) * width;
    double* dst = out.data() + static_cast<size_t>(y) * width;
    // Interior: taps outer, pixels inner (vectorises). Zero taps are skipped (adding 0 changes
    // nothing), which halves the cost of the one-sided feature lobes.
    const int lo = std::min(r, width), hi = std::max(lo, width - r);
    std::fill(dst + lo, dst + hi, 0.0);
    for (int k = -r; k <= r; ++k) {
      const double w = kernel[k + r];
      if (w == 0.0) continue;
      for (int x = lo; x < hi; ++x) dst[x] += w * src[x + k];
    }
    auto edge_pixel = [&](int x) {
      double acc = 0.0;
      for (int k = -r; k <= r; ++k) {
        int xx = x + k;
        if (xx < 0 || xx >= width) {
          if (border == Border::kZero) continue;
          xx = std::clamp(xx, 0, width - 1);
        }
        acc += kernel[k + r] * src[xx];
      }
      dst[x] = acc;
    };
    for (int x = 0; x < lo; ++x) edge_pixel(x);
    for (int x = hi; x < width; ++x) edge_pixel(x);
  });
}

void filter_cols(const std::vector<double>& in, int width, int height,
                 const std::vector<double>& kernel, Border border, std::vector<double>& out) {
  const int r = static_cast<int>(kernel.size() / 2);
  out.resize(in.size());
  for_rows(height, [&](int y) {
    double* dst = out.data() + static_cast<size_t>(y) * width;
    std::fill(dst, dst + width, 0.0);
    for (int k = -r; k <= r; ++k) {
      const double w = kernel[k + r];
      if (w == 0.0) continue;
      int yy = y + k;
      if (yy < 0 || yy >= height) {
        if (border == Border::kZero) continue;
        yy = std::clamp(yy, 0, height - 1);
      }
      const double* src = in.data() + static_cast<size_t>(yy) * width;
      for (int x = 0; x < width; ++x) dst[x] += w * src[x];
    }
  });
}

std::vector<double> filter_rows(const std::vector<double>& in, int width, int height,
                                const std::vector<double>& kernel, Border border) {
  std::vector<double> out;
  filter_rows(in, width, height, kernel, border, out);
  return out;
}

std::vector<double> filter_cols(const std::vector<double>& in, int width, int height,
                                const std::vector<double>& kernel, Border border) {
  std::vector<double> out;
  filter_cols(in, width, height, kernel, border, out);
  return out;
}

}  // namespace detail

namespace flip {

namespace {

using detail::Border;
using detail::filter_cols;
using detail::filter_rows;
using std::numbers::pi;

// Colour pipeline constants (paper, "colour metric").
constexpr double kQc = 0.7;
constexpr double kPc = 0.4;
constexpr double kPt = 0.95;
// Feature pipeline constants (paper, "feature pipeline").
constexpr double kQf = 0.5;
constexpr double kEdgeWidthDeg = 0.082;

// Gaussian-sum CSF approximations (paper, "spatial filtering").
struct GaussSum {
  double a1, b1, a2, b2;
};
constexpr GaussSum kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr GaussSum kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr GaussSum kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};

// CIELAB companding of a white-normalised tristimulus value.
double lab_f(double t) {
  constexpr double d = 6.0 / 29.0;
  return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

struct Lab {
  double L, a, b;
};

// Linear sRGB -> XYZ (D65) -> CIELAB, then the Hunt adjustment.
Lab hunt_lab(double r, double g, double b) {
  // The sRGB (D65) matrix as exact fractions, as in the authors' code.
  constexpr double m[3][3] = {
      {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
      {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
      {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
  const double white[3] = {m[0][0] + m[0][1] + m[0][2], m[1][0] + m[1][1] + m[1][2],
                           m[2][0] + m[2][1] + m[2][2]};
  double f[3];
  for (int i = 0; i < 3; ++i) f[i] = lab_f((m[i][0] * r + m[i][1] * g + m[i][2] * b) / white[i]);
  const double L = 116.0 * f[1] - 16.0;
  return {L, 0.01 * L * 500.0 * (f[0] - f[1]), 0.01 * L * 200.0 * (f[1] - f[2])};
}

double hyab(const Lab& p, const Lab& q) {
  return std::abs(p.L - q.L) + std::hypot(p.a - q.a, p.b - q.b);
}

// L* of grey linear luminance t (a* = b* = 0, unchanged by the Hunt adjustment).
double grey_lightness(double t) {
  return 116.0 * lab_f(t) - 16.0;
}

// 1-D factor of the achromatic CSF kernel. Its a2 is 0, so the 2-D kernel is one isotropic
// Gaussian, the outer product of this normalised 1-D kernel with itself. The radius is the one
// the paper's filters share across the three channels (set by the largest b).
std::vector<double> csf_kernel(double ppd) {
  double max_b = 0.0;
  for (const GaussSum& s : {kCsfAchromatic, kCsfRedGreen, kCsfBlueYellow})
    max_b = std::max({max_b, s.b1, s.b2});
  const int r = static_cast<int>(std::ceil(3.0 * std::sqrt(max_b / (2.0 * pi * pi)) * ppd));
  std::vector<double> k(2 * r + 1);
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) {
    const double x = i / ppd;  // degrees
    k[i + r] = std::exp(-pi * pi * x * x / kCsfAchromatic.b1);
    sum += k[i + r];
  }
  for (double& v : k) v /= sum;
  return k;
}

// The feature filters G(x) g(y) are separable: g is the 1-D Gaussian (normalised to sum 1) and
// G its first derivative (edges) or second derivative (points), whose positive and negative
// lobes we keep apart, each normalised to sum 1, so that with every pixel compared
// response = (G+ x g) * t - (G- x g) * t, the paper's filter with lobes normalised to +1 and -1.
struct FeatureKernels {
  std::vector<double> gauss;
  std::vector<double> lobes[4];  // edge+, edge-, point+, point-
};

FeatureKernels feature_kernels(double ppd) {
  const double sd = 0.5 * kEdgeWidthDeg * ppd;
  const int r = static_cast<int>(std::ceil(3.0 * sd));
  FeatureKernels fk;
  fk.gauss.resize(2 * r + 1);
  for (auto& l : fk.lobes) l.assign(2 * r + 1, 0.0);
  for (int i = -r; i <= r; ++i) {
    const double g = std::exp(-(i * i) / (2.0 * sd * sd));
    const double edge = -i * g;
    const double point = (i * i / (sd * sd) - 1.0) * g;
    fk.gauss[i + r] = g;
    fk.lobes[0][i + r] = std::max(edge, 0.0);
    fk.lobes[1][i + r] = std::max(-edge, 0.0);
    fk.lobes[2][i + r] = std::max(point, 0.0);
    fk.lobes[3][i + r] = std::max(-point, 0.0);
  }
  auto normalise = [](std::vector<double>& k) {
    double s = 0.0;
    for (double v : k) s += v;
    for (double& v : k) v /= s;
  };
  normalise(fk.gauss);
  for (auto& l : fk.lobes) normalise(l);
  return fk;
}

// Masked lobe response: weighted mean over the positive lobe minus that over the negative lobe.
double lobe_response(double pos_val, double pos_w, double neg_val, double neg_w) {
  constexpr double kMinWeight = 1e-12;
  if (pos_w <= kMinWeight || neg_w <= kMinWeight) return 0.0;
  return pos_val / pos_w - neg_val / neg_w;
}

}  // namespace

double pixels_per_degree(double distance_m, double width_m, double pixels_x) {
  return distance_m * (pixels_x / width_m) * (pi / 180.0);
}

// The reference side of the pipeline (issue 16): everything that depends on the reference and the
// mask only, computed once and reused for every estimate scored against that reference. The
// estimate side below runs the same operations in the same order as one pass over both would, so
// the map is the same bits either way (metrics_test).
ReferenceSide prepare_reference(int width, int height, const float* ref, const uint8_t* mask,
                                double ppd) {
  ReferenceSide r;
  r.width = width;
  r.height = height;
  r.ppd = ppd;
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  r.mask.assign(mask, mask + n);
  // Masked channels: the mask m and m * t, t = linear luminance Y/Yw of the displayed grey
  // (sRGB-encode the clamped AO, then FLIP's sRGB decode: the identity, so not computed).
  std::vector<double> m(n, 0.0), tr(n, 0.0);
  for (size_t p = 0; p < n; ++p) {
    if (!mask[p]) continue;
    m[p] = 1.0;
    tr[p] = std::clamp(static_cast<double>(ref[p]), 0.0, 1.0);
  }
  // Colour pipeline: masked CSF filtering of the achromatic channel.
  const std::vector<double> csf = csf_kernel(ppd);
  auto blur = [&](const std::vector<double>& c) {
    return filter_cols(filter_rows(c, width, height, csf, Border::kClamp), width, height, csf,
                       Border::kClamp);
  };
  // Feature pipeline: x-direction filters are lobe(x) gauss(y), y-direction ones gauss(x) lobe(y).
  const FeatureKernels fk = feature_kernels(ppd);
  std::vector<double> sq[2][2];  // the reference's squared responses [x, y][edges, points]
  auto direction = [&](int dir) {
    using Filter = void (*)(const std::vector<double>&, int, int, const std::vector<double>&,
                            Border, std::vector<double>&);
    const Filter first = dir == 0 ? Filter(filter_cols) : Filter(filter_rows);
    const Filter second = dir == 0 ? Filter(filter_rows) : Filter(filter_cols);
    std::vector<double> pre_m, pre_r, lobe_r[2];
    first(m, width, height, fk.gauss, Border::kClamp, pre_m);
    first(tr, width, height, fk.gauss, Border::kClamp, pre_r);
    for (int type = 0; type < 2; ++type) {
      for (int l = 0; l < 2; ++l) {
        second(pre_m, width, height, fk.lobes[2 * type + l], Border::kClamp,
               r.mask_lobes[dir][type][l]);
        second(pre_r, width, height, fk.lobes[2 * type + l], Border::kClamp, lobe_r[l]);
      }
      const auto& lobe_m = r.mask_lobes[dir][type];
      std::vector<double>& out = sq[dir][type];
      out.assign(n, 0.0);
      tbb::parallel_for(
          tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& rg) {
            for (size_t p = rg.begin(); p < rg.end(); ++p) {
              if (!mask[p]) continue;
              const double v =
                  lobe_response(lobe_r[0][p], lobe_m[0][p], lobe_r[1][p], lobe_m[1][p]);
              out[p] = v * v;
            }
          });
    }
  };
  // The four pieces side by side (issue 42, side_by_side.h); the two directions' squares are added
  // as one pass over both would add them, x then y: the same bits.
  detail::side_by_side([&] { r.wsum = blur(m); }, [&] { r.filtered = blur(tr); },
                       [&] { direction(0); }, [&] { direction(1); });
  for (int type = 0; type < 2; ++type) {
    r.squared[type].assign(n, 0.0);
    for (size_t p = 0; p < n; ++p) r.squared[type][p] = (0.0 + sq[0][type][p]) + sq[1][type][p];
  }
  return r;
}

namespace {

// The estimate's squared edge and point responses ([edges, points]) in one direction (0: x, 1: y)
// at the compared pixels, 0 elsewhere.
void feature_squares(const ReferenceSide& r, const std::vector<double>& te,
                     const FeatureKernels& fk, int dir, std::vector<double> (&out)[2]) {
  const int width = r.width, height = r.height;
  const size_t n = r.mask.size();
  const uint8_t* mask = r.mask.data();
  using Filter = void (*)(const std::vector<double>&, int, int, const std::vector<double>&, Border,
                          std::vector<double>&);
  const Filter first = dir == 0 ? Filter(filter_cols) : Filter(filter_rows);
  const Filter second = dir == 0 ? Filter(filter_rows) : Filter(filter_cols);
  std::vector<double> pre, lobe[2];
  first(te, width, height, fk.gauss, Border::kClamp, pre);
  for (int type = 0; type < 2; ++type) {
    for (int l = 0; l < 2; ++l)
      second(pre, width, height, fk.lobes[2 * type + l], Border::kClamp, lobe[l]);
    const auto& lobe_m = r.mask_lobes[dir][type];
    std::vector<double>& sq = out[type];
    sq.assign(n, 0.0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& rg) {
      for (size_t p = rg.begin(); p < rg.end(); ++p) {
        if (!mask[p]) continue;
        const double v = lobe_response(lobe[0][p], lobe_m[0][p], lobe[1][p], lobe_m[1][p]);
        sq[p] = v * v;
      }
    });
  }
}

}  // namespace

std::vector<float> error_map(const ReferenceSide& r, const float* est) {
  const int width = r.width, height = r.height;
  const size_t n = r.mask.size();
  const uint8_t* mask = r.mask.data();
  std::vector<double> te(n, 0.0);
  for (size_t p = 0; p < n; ++p)
    if (mask[p]) te[p] = std::clamp(static_cast<double>(est[p]), 0.0, 1.0);
  const std::vector<double> csf = csf_kernel(r.ppd);
  const FeatureKernels fk = feature_kernels(r.ppd);
  // The colour pipeline and the two directions' features side by side (issue 42, side_by_side.h);
  // each direction's squared responses are added as one pass over both would add them, x then y:
  // the same bits.
  std::vector<double> fe;
  std::vector<double> sq[2][2];  // [x, y][edges, points]
  detail::side_by_side(
      [&] {
        fe = filter_cols(filter_rows(te, width, height, csf, Border::kClamp), width, height, csf,
                         Border::kClamp);
      },
      [&] { feature_squares(r, te, fk, 0, sq[0]); }, [&] { feature_squares(r, te, fk, 1, sq[1]); });

  const double cmax = std::pow(hyab(hunt_lab(0, 1, 0), hunt_lab(0, 0, 1)), kQc);
  const double pccmax = kPc * cmax;
  std::vector<float> out(n, 0.0f);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& rg) {
    for (size_t p = rg.begin(); p < rg.end(); ++p) {
      if (!mask[p]) continue;
      // Colour: filtered grey, clamped to the RGB cube, to L*; HyAB = |dL*| for grey.
      const double gr = std::clamp(r.filtered[p] / r.wsum[p], 0.0, 1.0);
      const double ge = std::clamp(fe[p] / r.wsum[p], 0.0, 1.0);
      const double e = std::pow(std::abs(grey_lightness(gr) - grey_lightness(ge)), kQc);
      const double dec =
          e < pccmax ? (kPt / pccmax) * e : kPt + ((e - pccmax) / (cmax - pccmax)) * (1.0 - kPt);
      // Features: norms of the (x, y) responses of edges and points.
      const double edges = (0.0 + sq[0][0][p]) + sq[1][0][p];
      const double points = (0.0 + sq[0][1][p]) + sq[1][1][p];
      const double edge = std::abs(std::sqrt(r.squared[0][p]) - std::sqrt(edges));
      const double point = std::abs(std::sqrt(r.squared[1][p]) - std::sqrt(points));
      const double feature = std::max(edge, point);
      const double def = std::pow(feature / std::numbers::sqrt2, kQf);
      out[p] = static_cast<float>(std::pow(dec, 1.0 - def));
    }
  });
  return out;
}

std::vector<float> error_map(int width, int height, const float* ref, const float* est,
                             const uint8_t* mask, double ppd) {
  return error_map(prepare_reference(width, height, ref, mask, ppd), est);
}

}  // namespace flip

}  // namespace aoeval
