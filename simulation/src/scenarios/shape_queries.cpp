#include "scenarios/shape_queries.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navaid::simulation::detail {

bool point_in_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double polygon_distance(const std::vector<Vec2>& poly, const Vec2& p) {
  if (point_in_polygon(poly, p)) return 0.0;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) d = std::min(d, segment_distance(p, poly[j], poly[i]));
  return d;
}

double rectangle_distance(const Vec2& p, const Vec2& c, const Vec2& h, double yaw) {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const Vec2 d = p - c;
  const Vec2 local(cy * d.x() + sy * d.y(), -sy * d.x() + cy * d.y());
  const Vec2 outside = (local.cwiseAbs() - h).cwiseMax(0.0);
  return outside.norm();
}

bool segment_crosses_open_rect(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi) {
  // Liang-Barsky clipping against the open box: a non-empty open parameter interval remains.
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (!(a[k] > lo[k] && a[k] < hi[k])) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t1 - t0 > 1e-12)) return false;
  }
  return true;
}

bool is_upright(const Quat& q, double* yaw) {
  const Mat3 R = q.toRotationMatrix();
  if (std::abs(R(2, 2) - 1.0) > 1e-9) return false;
  *yaw = std::atan2(R(1, 0), R(0, 0));
  return true;
}

}  // namespace navaid::simulation::detail
