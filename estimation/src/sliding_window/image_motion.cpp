#include "image_motion.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace navaid::estimation::sliding_window {

ImageMotion image_motion(const FeatureFrame& from, const FeatureFrame& to) {
  std::vector<double> moved, du, dv;
  auto a = from.features.begin();
  auto b = to.features.begin();
  while (a != from.features.end() && b != to.features.end()) {
    if (a->track_id < b->track_id) {
      ++a;
    } else if (b->track_id < a->track_id) {
      ++b;
    } else {
      const Eigen::Vector2d d = b->uv - a->uv;
      moved.push_back(d.norm());
      du.push_back(d.x());
      dv.push_back(d.y());
      ++a, ++b;
    }
  }
  ImageMotion m;
  m.common = moved.size();
  if (moved.empty()) return m;
  const auto median = [](std::vector<double>& x) {
    const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
    std::nth_element(x.begin(), mid, x.end());
    return *mid;
  };
  m.median_px = median(moved);
  m.shift_px = std::hypot(median(du), median(dv));
  return m;
}

std::optional<ImageMotion> image_motion_over(const std::deque<FeatureFrame>& recent, const FeatureFrame& frame,
                                             double span_s) {
  const Timestamp span = static_cast<Timestamp>(std::llround(span_s * 1e9));
  for (const FeatureFrame& f : recent) {  // oldest first
    if (f.t < frame.t - span || f.camera != frame.camera) continue;
    if (frame.t - f.t < span / 2) return std::nullopt;
    return image_motion(f, frame);
  }
  return std::nullopt;
}

}  // namespace navaid::estimation::sliding_window
