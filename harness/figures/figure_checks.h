// The checks of the Hegeman, Mendez, Dimitrov and GPU Gems fig17-3 figures as functions of their
// numbers, so that a test can feed them synthetic numbers and show each figure's checks passing and
// failing (figure_checks_test.cpp); each figure computes its numbers and calls its function. Timing
// numbers are the interleaved repetitions themselves, decided by a rank test (figure_timing.h).
#pragma once

#include <string>
#include <vector>

#include "harness/figures/figure.h"

namespace aoeval::figures {

// hegeman-fig2: per scene (sphere-uniform, sphere-uniform-dense, tree-apple, tree-poplar), the
// tile RMSE and tile Pearson r of eq. 6 as derived, eq. 6 at its best alpha rho scale and
// tree-volume, each against the truth.
struct TileScore {
  double rmse = 0.0, pearson = 0.0;
};
struct Fig2Numbers {
  std::vector<std::string> scenes;
  std::vector<TileScore> derived, best, volume;
  std::vector<double> best_scale;
};
std::vector<Check> hegeman_fig2_checks(const Fig2Numbers& n);

// hegeman-fig8: tile RMSE of ellipsoid, sphere, shells on the poplar; mean |ellipsoid - sphere|.
struct Fig8Numbers {
  double ellipsoid = 0.0, sphere = 0.0, shells = 0.0, difference = 0.0;
};
std::vector<Check> hegeman_fig8_checks(const Fig8Numbers& n);

// hegeman-fig12: per view (two), tree-pixel RMSE and Pearson r of ours, Reeves-Blau, ambient.
struct Fig12Numbers {
  std::vector<std::string> views;
  std::vector<std::vector<double>> rmse, pearson;  // [view][ours, reeves-blau, ambient]
};
std::vector<Check> hegeman_fig12_checks(const Fig12Numbers& n);

// hegeman-throughput: interleaved frame times (ms) of ours, Reeves-Blau and ambient only.
struct ThroughputNumbers {
  std::vector<double> ours, reeves_blau, ambient;
};
std::vector<Check> hegeman_throughput_checks(const ThroughputNumbers& n);

// mendez-fig6: per ray count, mean and standard error over seeds of random and systematic RMSE.
struct Fig6Numbers {
  std::vector<int> rays;
  std::vector<double> random_mean, random_se, systematic_mean, systematic_se;
};
std::vector<Check> mendez_fig6_checks(const Fig6Numbers& n);

// mendez-fig7: per dmax (0.2, 0.5, 1.0, 2.0), the mean obscurance and the interleaved frame times.
struct Fig7Numbers {
  std::vector<double> dmax, mean;
  std::vector<std::vector<double>> ms;
};
std::vector<Check> mendez_fig7_checks(const Fig7Numbers& n);

// gpugems-fig17-3: vertex-baked on the coarsest and the finest floor, shadowmap-ao per vertex on
// the finest (has_shadowmap false when its backend is missing), and the reference's contrast.
struct Fig17Numbers {
  bool have_fine = false, have_coarse = false, have_shadowmap = false;
  double fine_model_r = 0.0, fine_shadow = 0.0, coarse_shadow = 0.0, ref_shadow = 0.0;
  double fine_rmse = 0.0, shadowmap_model_r = 0.0, shadowmap_shadow = 0.0, shadowmap_rmse = 0.0;
  std::string contrast;  // "2 floor triangles: 0.006, ..." for the caption
};
std::vector<Check> gpugems_fig17_checks(const Fig17Numbers& n);

// equal-time: per scene, the contenders' chosen points against the budget (the ones outside a
// factor 1.5, as "estimator on scene t ms vs budget"), the scene's winner by matched rmse_excess,
// and gtao's bent_angle_excess where it has one.
struct EqualTimeNumbers {
  size_t scenes = 0;  // scenes in the figure
  std::vector<std::string> timing_misses;
  std::vector<std::string> winners;      // "scene: estimator", one per scene scored
  std::vector<double> gtao_bent_excess;  // degrees, one per scene where gtao had bent normals
};
std::vector<Check> equal_time_checks(const EqualTimeNumbers& n);

// dimitrov-fig6: mean AO and matched RMSE per R (ascending).
struct DimitrovFig6Numbers {
  std::vector<double> mean, rmse;
};
std::vector<Check> dimitrov_fig6_checks(const DimitrovFig6Numbers& n);

// dimitrov-fig7: matched RMSE at Nd 1, 4, 10 and the interleaved frame times at Nd 1 and 16.
struct DimitrovFig7Numbers {
  double rmse_nd1 = 0.0, rmse_nd4 = 0.0, rmse_nd10 = 0.0;
  std::vector<double> ms_nd1, ms_nd16;
};
std::vector<Check> dimitrov_fig7_checks(const DimitrovFig7Numbers& n);

// dimitrov-fig11: matched RMSE and interleaved frame times of presets (a) to (d).
struct DimitrovFig11Numbers {
  std::vector<double> rmse;
  std::vector<std::vector<double>> ms;
};
std::vector<Check> dimitrov_fig11_checks(const DimitrovFig11Numbers& n);

// dimitrov-fig12: matched RMSE of horizon split and ray marching per rays-per-pixel budget.
struct DimitrovFig12Numbers {
  std::vector<int> budgets;
  std::vector<double> horizon_split, ray_marching;
};
std::vector<Check> dimitrov_fig12_checks(const DimitrovFig12Numbers& n);

// dimitrov-table1: per resolution row, the interleaved per-pass samples (ms) and the paper's row.
struct Table1Numbers {
  std::vector<std::vector<double>> ho, no, blur, geo;  // geo empty where no geometry pass
  std::vector<double> paper_ho_over_no, paper_ho, pixels, paper_pixels;
};
std::vector<Check> dimitrov_table1_checks(const Table1Numbers& n);

}  // namespace aoeval::figures
