// The walkability rule: horizontal clearance of a walker's body band to static geometry.
#include <algorithm>
#include <cmath>
#include <limits>

#include "navaid/simulation/scenario.hpp"
#include "scenarios/shape_queries.hpp"

namespace navaid::simulation {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Conservative horizontal distance via the bounding box (tilted boxes and patches).
double aabb_band_distance(const AxisAlignedBox& b, const Vec2& p, double z_lo, double z_hi) {
  const double dx = std::max({b.min.x() - p.x(), 0.0, p.x() - b.max.x()});
  const double dy = std::max({b.min.y() - p.y(), 0.0, p.y() - b.max.y()});
  if (b.max.z() <= z_lo || b.min.z() >= z_hi) return kInf;
  return std::hypot(dx, dy);
}

double ellipsoid_distance(const Ellipsoid& e, const Vec2& p, double z_lo, double z_hi) {
  const Vec3 c = e.T_W_O.t;
  double yaw = 0.0;
  if (detail::is_upright(e.T_W_O.q, &yaw)) {
    // Widest slice within the band: at the band height nearest the centre.
    const double z = std::clamp(c.z(), z_lo, z_hi);
    const double f = 1.0 - std::pow((z - c.z()) / e.radii.z(), 2);
    if (f <= 0.0) return kInf;
    const double k = std::sqrt(f);
    const double a = k * e.radii.x(), b = k * e.radii.y();
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    const Vec2 d = p - c.head<2>();
    const Vec2 local(cy * d.x() + sy * d.y(), -sy * d.x() + cy * d.y());
    const double q = std::hypot(local.x() / a, local.y() / b);
    // Lower bound of the distance to the slice ellipse (exact for circles).
    return std::max(0.0, (q - 1.0) * std::min(a, b));
  }
  // Tilted ellipsoid: distance from the band segment in the unit-sphere frame, scaled by the
  // smallest radius (a lower bound, since that map stretches distances by at most 1 / r_min).
  const Vec3 lo(p.x(), p.y(), z_lo), hi(p.x(), p.y(), z_hi);
  const Mat3 Rt = e.T_W_O.q.conjugate().toRotationMatrix();
  const Vec3 a = (Rt * (lo - c)).cwiseQuotient(e.radii), b = (Rt * (hi - c)).cwiseQuotient(e.radii);
  const Vec3 ab = b - a;
  const double t = std::clamp(-a.dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return std::max(0.0, ((a + t * ab).norm() - 1.0) * e.radii.minCoeff());
}

}  // namespace

double horizontal_distance(const Shape& shape, const Vec2& p, double z_lo, double z_hi) {
  auto band_overlap = [&](double lo, double hi) { return hi > z_lo && lo < z_hi; };
  return std::visit(
      [&](const auto& s) -> double {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, VerticalCylinder>) {
          if (!band_overlap(s.base_center.z(), s.base_center.z() + s.height)) return kInf;
          return std::max(0.0, (p - s.base_center.template head<2>()).norm() - s.radius);
        } else if constexpr (std::is_same_v<T, ExtrudedPolygon>) {
          if (!band_overlap(s.z_min, s.z_max)) return kInf;
          return detail::polygon_distance(s.polygon, p);
        } else if constexpr (std::is_same_v<T, Box>) {
          double yaw = 0.0;
          if (!detail::is_upright(s.T_W_O.q, &yaw)) return aabb_band_distance(bounds_of(shape), p, z_lo, z_hi);
          if (!band_overlap(s.T_W_O.t.z() - s.half_extents.z(), s.T_W_O.t.z() + s.half_extents.z())) return kInf;
          return detail::rectangle_distance(p, s.T_W_O.t.template head<2>(), s.half_extents.template head<2>(), yaw);
        } else if constexpr (std::is_same_v<T, PlanePatch>) {
          double yaw = 0.0;
          if (detail::is_upright(s.T_W_P.q, &yaw) || detail::is_upright(s.T_W_P.q * Quat(0, 1, 0, 0), &yaw)) {
            const double z = s.T_W_P.t.z();  // horizontal patch: a sheet at one height
            if (!(z > z_lo && z < z_hi)) return kInf;
            return detail::rectangle_distance(p, s.T_W_P.t.template head<2>(), Vec2(s.half_x, s.half_y), yaw);
          }
          return aabb_band_distance(bounds_of(shape), p, z_lo, z_hi);
        } else {
          return ellipsoid_distance(s, p, z_lo, z_hi);
        }
      },
      shape);
}

double horizontal_clearance(const World& world, const Vec2& p, double ground_z_m, const ClearanceBand& band,
                            const std::vector<std::uint32_t>& ignore) {
  const double z_lo = ground_z_m + band.z_min_m, z_hi = ground_z_m + band.z_max_m;
  double best = kInf;
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    if (std::find(ignore.begin(), ignore.end(), i) != ignore.end()) continue;
    best = std::min(best, horizontal_distance(world.primitive(i).shape, p, z_lo, z_hi));
  }
  return best;
}

double path_clearance(const World& world, const std::vector<Vec2>& path, double ground_z_m, double step_m,
                      const ClearanceBand& band, const std::vector<std::uint32_t>& ignore) {
  double best = kInf;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Vec2 a = path[i], b = path[i + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_m)));
    for (int k = 0; k <= n; ++k)
      best = std::min(best, horizontal_clearance(world, a + (b - a) * (static_cast<double>(k) / n), ground_z_m, band, ignore));
  }
  if (path.size() == 1) best = horizontal_clearance(world, path.front(), ground_z_m, band, ignore);
  return best;
}

}  // namespace navaid::simulation
