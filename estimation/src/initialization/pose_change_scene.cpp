#include "navaid/estimation/initialization/pose_change_scene.hpp"

#include <cmath>
#include <random>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::estimation {

TwoViewScene make_two_view_scene(const SE3& T_j_i, const TwoViewSceneOptions& o) {
  if (o.points < 1 || !(o.min_depth_m > 0.0) || !(o.max_depth_m >= o.min_depth_m) || !(o.half_fov > 0.0) ||
      !(o.focal_px > 0.0) || !(o.pixel_noise_px >= 0.0) || !(o.depth_noise_rel >= 0.0) ||
      !(o.outlier_fraction >= 0.0 && o.outlier_fraction <= 1.0))
    throw Error("two-view scene: invalid options");
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> plane(-o.half_fov, o.half_fov);
  std::uniform_real_distribution<double> depth(o.min_depth_m, o.max_depth_m);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, o.pixel_noise_px / o.focal_px);
  std::normal_distribution<double> gauss(0.0, 1.0);

  TwoViewScene s;
  s.T_j_i = T_j_i;
  const int outliers = static_cast<int>(std::lround(o.outlier_fraction * o.points));
  const int with_depth = o.depth_features < 0 ? o.points : o.depth_features;
  for (long attempt = 0; static_cast<int>(s.correspondences.size()) < o.points; ++attempt) {
    if (attempt > 1000L * o.points) throw Error("two-view scene: too few points visible in both frames");
    const Vec2 m = draw_vector<2>([&] { return plane(rng); });
    const double Z = depth(rng);
    const Vec3 X_j = T_j_i * Vec3(Z * m.x(), Z * m.y(), Z);
    if (!(X_j.z() > 0.1)) continue;
    const Vec2 m_j = X_j.head<2>() / X_j.z();
    if (std::abs(m_j.x()) > o.half_fov || std::abs(m_j.y()) > o.half_fov) continue;
    const int k = static_cast<int>(s.correspondences.size());
    PoseChangeCorrespondence c;
    c.m_i = m + draw_vector<2>([&] { return noise(rng); });
    c.m_j = m_j + draw_vector<2>([&] { return noise(rng); });
    if (k < with_depth) c.depth_i = Z * std::max(0.05, 1.0 + o.depth_noise_rel * gauss(rng));
    s.correspondences.push_back(c);
  }
  s.outlier.assign(s.correspondences.size(), 0);
  // Outliers spread evenly over depth and no-depth features (every k-th), far from the truth.
  for (int n = 0; n < outliers; ++n) {
    const int k = static_cast<int>((static_cast<long>(n) * o.points) / outliers);
    auto& c = s.correspondences[k];
    Vec2 r;
    do r = draw_vector<2>([&] { return plane(rng); });
    while ((r - c.m_j).norm() * o.focal_px < 20.0);
    c.m_j = r;
    s.outlier[k] = 1;
  }
  return s;
}

}  // namespace navaid::estimation
