#include "navaid/estimation/frontend/depth_association.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace navaid::estimation {

std::optional<double> associate_depth(const ImageF32& depth, const Eigen::Vector2d& uv, const DepthPatchOptions& o) {
  if (depth.empty() || !uv.allFinite()) return std::nullopt;
  const long cx = std::lround(uv.x()), cy = std::lround(uv.y());
  const int half = o.patch_size / 2;
  std::array<float, 81> values{};  // patches up to 9x9
  std::size_t n = 0;
  for (long y = cy - half; y <= cy + half; ++y) {
    if (y < 0 || y >= depth.height) continue;
    for (long x = cx - half; x <= cx + half; ++x) {
      if (x < 0 || x >= depth.width || n == values.size()) continue;
      const float d = depth.at(static_cast<int>(x), static_cast<int>(y));
      if (d > 0.0f && std::isfinite(d)) values[n++] = d;
    }
  }
  if (n == 0 || n < static_cast<std::size_t>(o.min_valid)) return std::nullopt;
  std::sort(values.begin(), values.begin() + static_cast<long>(n));
  const double median = n % 2 == 1 ? values[n / 2] : 0.5 * (double(values[n / 2 - 1]) + double(values[n / 2]));
  // A patch straddling a silhouette mixes foreground and background: its median is neither.
  if (double(values[n - 1]) - double(values[0]) > o.max_relative_spread * median) return std::nullopt;
  if (median < o.min_depth_m || median > o.max_depth_m) return std::nullopt;
  return median;
}

}  // namespace navaid::estimation
