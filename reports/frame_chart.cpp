#include "reports/frame_chart.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace aoeval {

namespace {

constexpr double kWidth = 480, kHeight = 120, kLeft = 56, kRight = 8, kTop = 8, kBottom = 22;

std::optional<double> value_of(const FrameRow& f, const std::string& figure) {
  if (figure == "time_ms") return f.time_ms;
  const auto it = f.metrics.find(figure);
  if (it == f.metrics.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

}  // namespace

Html frame_chart(const std::vector<FrameRow>& before, const std::vector<FrameRow>& after,
                 const std::string& figure) {
  int last_frame = 1;
  double top = 0.0;
  bool any = false;
  for (const auto* run : {&before, &after})
    for (const FrameRow& f : *run)
      if (const auto v = value_of(f, figure); v && std::isfinite(*v)) {
        any = true;
        top = std::max(top, *v);
        last_frame = std::max(last_frame, f.frame);
      }
  if (!any) return {};
  if (top <= 0.0) top = 1.0;
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  auto line = [&](const std::vector<FrameRow>& frames, Literal attributes) {
    Html points;
    for (const FrameRow& f : frames)
      if (const auto v = value_of(f, figure); v && std::isfinite(*v))
        points << number(kLeft + plot_w * f.frame / last_frame, "%.1f") << ","
               << number(kTop + plot_h * (1.0 - *v / top), "%.1f") << " ";
    return Html("<polyline fill=\"none\" ") << attributes << " points=\"" << points << "\"/>";
  };
  Html h(
      "<figure class=\"frame-chart\"><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"480\" "
      "height=\"120\" viewBox=\"0 0 480 120\" role=\"img\"><title>");
  h << text(figure) << " by frame: baseline (grey) and new (blue)</title>"
    << "<line x1=\"56\" y1=\"98\" x2=\"472\" y2=\"98\" stroke=\"#888\"/>"
    << "<line x1=\"56\" y1=\"8\" x2=\"56\" y2=\"98\" stroke=\"#888\"/>"
    << "<text x=\"52\" y=\"16\" text-anchor=\"end\" font-size=\"10\">" << number(top)
    << "</text><text x=\"52\" y=\"98\" text-anchor=\"end\" font-size=\"10\">0</text>"
    << "<text x=\"56\" y=\"114\" font-size=\"10\">frame 0</text>"
    << "<text x=\"472\" y=\"114\" text-anchor=\"end\" font-size=\"10\">frame " << last_frame
    << "</text>" << line(before, "class=\"baseline\" stroke=\"#999\" stroke-width=\"2\"")
    << line(after, "class=\"new\" stroke=\"#1f77b4\" stroke-width=\"1.5\"") << "</svg><figcaption>"
    << text(figure) << " by frame: baseline (grey) and new (blue)</figcaption></figure>\n";
  return h;
}

}  // namespace aoeval
