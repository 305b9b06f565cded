#include "image_motion.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace navaid::estimation::sliding_window {

ImageMotion image_motion(const FeatureFrame& from, const FeatureFrame& to) {
  std::vector<double> moved;
  auto a = from.features.begin();
  auto b = to.features.begin();
  while (a != from.features.end() && b != to.features.end()) {
    if (a->track_id < b->track_id) {
      ++a;
    } else if (b->track_id < a->track_id) {
      ++b;
    } else {
      moved.push_back((b->uv - a->uv).norm());
      ++a, ++b;
    }
  }
  ImageMotion m;
  m.common = moved.size();
  if (moved.empty()) return m;
  const auto mid = moved.begin() + static_cast<std::ptrdiff_t>(moved.size() / 2);
  std::nth_element(moved.begin(), mid, moved.end());
  m.median_px = *mid;
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
