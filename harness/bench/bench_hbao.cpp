// `aoeval bench hbao`: fetch efficiency of hbao-split against a bare fetch loop, and the Vulkan
// twin against the CPU twin on the same G-buffer (see bench_hbao.h).
#include "harness/bench/bench_hbao.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "base/summary.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/screen_space/frame_device.h"
#include "harness/bench/twin_bench.h"

namespace aoeval {

namespace {

// The mean screen-space length of one step R / Ns at the covered pixels' depths, pixels.
double mean_step_pixels(const ScreenSpaceFrame& f, const HbaoSettings& s) {
  const double step = s.radius / s.steps;
  double sum = 0.0;
  size_t n = 0;
  for (float z : f.depth) {
    if (!(z > 0.0f)) continue;
    sum += step * f.focal / z;
    ++n;
  }
  return n ? sum / static_cast<double>(n) : 1.0;
}

}  // namespace

void bench_hbao(const HbaoBenchOptions& o) {
  const TwinBench b(o, "hbao-split", "hbao-split-cpu");
  if (!b.vk) {
    std::printf("bench hbao: skipped: no Vulkan device (%s)\n", b.skip_reason.c_str());
    return;
  }
  const HbaoSettings s = hbao_settings_of(b.cpu_params);
  const int w = b.camera.width, h = b.camera.height;

  // hbao-split on the device; its first frame gives the G-buffer for the CPU twin.
  const std::unique_ptr<HbaoDevice> device =
      make_frame_device<HbaoDevice>(*b.vk, s, b.raster, b.scene, b.gbuffer);
  const HbaoGpuResult first = device->run();

  // hbao-split-cpu on that G-buffer: the exact fetch count and the twin check.
  const ScreenSpaceFrame frame = device->frame();
  const HbaoCpuResult counted = hbao_split_cpu(frame, s, true);
  const double twin_diff = hbao_max_abs_difference(frame, counted.ao, first.ao);

  // The bare fetch loop: as many fetches per pixel, along walks of the same screen step.
  const double pixels = static_cast<double>(w) * h;
  const auto fetches = static_cast<double>(counted.depth_fetches);
  const int walks = s.directions * (1 + s.normal_rays);
  const int steps = std::max(1, static_cast<int>(std::lround(fetches / pixels / walks)));
  const double step_px = mean_step_pixels(frame, s);
  const double bare_fetches = pixels * walks * steps;
  BareFetch bare(*b.vk, device->depth_image(), walks, steps, static_cast<float>(step_px));

  // Timed on the device, alternating hbao-split and the bare loop repetition by repetition, so
  // that both see the same load (this machine is shared: the load drifts between runs, and a
  // ratio of two medians taken minutes apart carried it). Each repetition gives a ratio.
  for (int i = 0; i < o.warmup; ++i) {
    device->run();
    bare.run_ms();
  }
  std::vector<PassTimes> gpu_runs;
  std::vector<double> gpu_totals, bare_runs, ratios;
  for (int i = 0; i < o.repetitions; ++i) {
    const HbaoGpuResult r = device->run();
    const double bare_ms_i = bare.run_ms();
    gpu_runs.push_back(r.pass_ms);
    gpu_totals.push_back(pass_ms(r.pass_ms, "total_ms"));
    bare_runs.push_back(bare_ms_i);
    const double tracing_i = pass_ms(r.pass_ms, "horizon_ms") + pass_ms(r.pass_ms, "normal_ms");
    ratios.push_back((fetches / tracing_i) / (bare_fetches / bare_ms_i));
  }
  const PassTimes gpu = pass_medians(gpu_runs);
  const double bare_ms = median(bare_runs);
  const double ratio = median(ratios);

  // hbao-split-cpu's times.
  for (int i = 0; i < o.warmup; ++i) hbao_split_cpu(frame, s);
  std::vector<PassTimes> cpu_runs;
  std::vector<double> cpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const HbaoCpuResult r = hbao_split_cpu(frame, s);
    const double total = r.horizon_ms + r.normal_ms + r.blur_ms;
    cpu_runs.push_back(
        {{"horizon_ms", r.horizon_ms}, {"normal_ms", r.normal_ms}, {"blur_ms", r.blur_ms}});
    cpu_totals.push_back(total);
  }
  const PassTimes cpu = pass_medians(cpu_runs);
  const double cpu_total = median(cpu_totals);

  const double tracing_ms = pass_ms(gpu, "horizon_ms") + pass_ms(gpu, "normal_ms");
  const double hbao_rate = fetches / (tracing_ms * 1e-3);
  const double bare_rate = bare_fetches / (bare_ms * 1e-3);
  const double gpu_ao_ms = tracing_ms + pass_ms(gpu, "blur_ms");
  const double speedup = cpu_total / gpu_ao_ms;

  nlohmann::json j = b.summary(gpu, cpu, cpu_total, gpu_ao_ms);
  j["depth_fetches"] = counted.depth_fetches;
  j["hbao_fetches_per_s"] = hbao_rate;
  j["bare_walks"] = walks;
  j["bare_steps"] = steps;
  j["bare_step_px"] = step_px;
  j["bare_ms"] = bare_ms;
  j["bare_fetches_per_s"] = bare_rate;
  j["fetch_ratio"] = ratio;
  j["fetch_ratios"] = ratios;
  j["fetch_ratio_target"] = 0.5;
  j["twin_max_abs_difference"] = twin_diff;

  std::ostringstream md;
  b.write_pass_table(md, "hbao-split bench", {"geometry_ms", "horizon_ms", "normal_ms", "blur_ms"},
                     gpu, cpu, cpu_total);
  md << "- AO passes, CPU twin / GPU: " << format_number("%.2fx", speedup) << "\n"
     << "- depth fetches (horizon + normal passes): " << counted.depth_fetches << " ("
     << format_number("%.1f", fetches / pixels) << " per pixel)\n"
     << "- hbao-split: " << format_number("%.3f", hbao_rate * 1e-9) << " Gfetch/s; bare loop ("
     << walks << " walks x " << steps << " steps of " << format_number("%.2f", step_px)
     << " px): " << format_number("%.3f", bare_rate * 1e-9) << " Gfetch/s in "
     << format_number("%.3f", bare_ms) << " ms\n"
     << "- fetch ratio " << format_number("%.3f", ratio) << " (median of " << ratios.size()
     << " repetitions, each hbao-split's rate over the bare loop's timed right after it; "
     << format_number("%.3f", *std::min_element(ratios.begin(), ratios.end())) << " to "
     << format_number("%.3f", *std::max_element(ratios.begin(), ratios.end()))
     << "; target >= 0.5: " << (ratio >= 0.5 ? "met" : "NOT met") << ")\n"
     << "- twin max |CPU - GPU| over covered pixels: " << format_number("%.3g", twin_diff) << "\n"
     << "- " << b.geometry_note() << "\n";
  b.write("bench hbao", "bench_hbao", j, md.str(), gpu_totals, gpu, cpu_totals, cpu);
}

}  // namespace aoeval
