// `aoeval bench gtao` (see bench_gtao.h).
#include "harness/bench/bench_gtao.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "base/summary.h"
#include "estimators/gtao/gtao.h"
#include "estimators/gtao/gtao_vulkan.h"
#include "estimators/screen_space/frame_device.h"
#include "harness/bench/twin_bench.h"

namespace aoeval {

void bench_gtao(const GtaoBenchOptions& o) {
  const TwinBench b(o, "gtao", "gtao-cpu");
  if (!b.vk) {
    std::printf("bench gtao: skipped: no Vulkan device (%s)\n", b.skip_reason.c_str());
    return;
  }
  const GtaoSettings s = gtao_settings_of(b.cpu_params);
  const std::unique_ptr<GtaoDevice> device =
      make_frame_device<GtaoDevice>(*b.vk, s, b.raster, b.scene, b.gbuffer);
  const GtaoOutput first = device->run();
  const ScreenSpaceFrame frame = device->frame();
  const GtaoOutput twin = gtao_cpu(frame, b.camera, s);
  double ao_diff = 0.0, bent_diff = 0.0;
  size_t covered = 0, not_identical = 0;
  for (size_t k = 0; k < frame.depth.size(); ++k) {
    if (!(frame.depth[k] > 0.0f)) continue;
    ++covered;
    ao_diff = std::max(ao_diff, std::abs(static_cast<double>(first.ao[k]) - twin.ao[k]));
    bool same = first.ao[k] == twin.ao[k];
    if (s.bent) {
      bent_diff =
          std::max(bent_diff, static_cast<double>(glm::length(first.bent[k] - twin.bent[k])));
      same = same && first.bent[k] == twin.bent[k];
    }
    not_identical += same ? 0 : 1;
  }

  for (int i = 0; i < o.warmup; ++i) device->run();
  std::vector<PassTimes> gpu_runs;
  std::vector<double> gpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const GtaoOutput r = device->run();
    gpu_runs.push_back(r.pass_ms);
    gpu_totals.push_back(pass_ms(r.pass_ms, "total_ms"));
  }
  for (int i = 0; i < o.warmup; ++i) gtao_cpu(frame, b.camera, s);
  std::vector<PassTimes> cpu_runs;
  std::vector<double> cpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const GtaoOutput r = gtao_cpu(frame, b.camera, s);
    cpu_runs.push_back(r.pass_ms);
    cpu_totals.push_back(pass_ms(r.pass_ms, "horizon_ms") + pass_ms(r.pass_ms, "denoise_ms"));
  }
  const PassTimes gpu = pass_medians(gpu_runs), cpu = pass_medians(cpu_runs);
  const double cpu_total = median(cpu_totals);
  const double gpu_ao_ms = pass_ms(gpu, "horizon_ms") + pass_ms(gpu, "denoise_ms");
  const double samples = static_cast<double>(covered) * s.slices * 2.0 * s.steps;
  const double sample_rate = samples / (pass_ms(gpu, "horizon_ms") * 1e-3);

  nlohmann::json j = b.summary(gpu, cpu, cpu_total, gpu_ao_ms);
  j["covered_pixels"] = covered;
  j["horizon_samples"] = samples;
  j["horizon_samples_per_s"] = sample_rate;
  j["depth_fetches_per_s"] = 4.0 * sample_rate;
  j["twin_max_abs_difference"] = ao_diff;
  j["twin_bent_max_difference"] = bent_diff;
  j["twin_pixels_not_bit_identical"] = not_identical;

  std::ostringstream md;
  b.write_pass_table(md, "gtao bench", {"geometry_ms", "horizon_ms", "denoise_ms"}, gpu, cpu,
                     cpu_total);
  md << "- AO passes, CPU twin / GPU: " << format_number("%.2fx", cpu_total / gpu_ao_ms) << "\n"
     << "- horizon samples: " << format_number("%.0f", samples) << " (" << s.slices
     << " slices x 2 x " << s.steps << " steps x " << covered << " covered pixels), "
     << format_number("%.1f", sample_rate * 1e-6) << " Msample/s, "
     << format_number("%.1f", 4.0 * sample_rate * 1e-6) << " M depth fetches/s\n"
     << "- twins: max |CPU - GPU| AO " << format_number("%.3g", ao_diff) << ", bent "
     << format_number("%.3g", bent_diff) << "; " << not_identical << " of " << covered
     << " covered pixels not bit-identical\n"
     << "- " << b.geometry_note() << "\n";
  b.write("bench gtao", "bench_gtao", j, md.str(), gpu_totals, gpu, cpu_totals, cpu);
}

}  // namespace aoeval
