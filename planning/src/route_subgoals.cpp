#include "navaid/planning/route_subgoals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {

constexpr double kRouteSubgoalsDeg = 3.14159265358979323846 / 180.0;

/// Closest point of segment ab to p: the parameter t in [0, 1].
double closest_t(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  return len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
}

}  // namespace

LocalEnu::LocalEnu(const GeodeticOrigin& origin) : origin_(origin) {
  constexpr double a = 6378137.0;              // WGS84 semi-major axis
  constexpr double e2 = 6.69437999014e-3;      // first eccentricity squared
  const double s = std::sin(origin.latitude_deg * kRouteSubgoalsDeg);
  const double w = 1.0 - e2 * s * s;
  const double meridian = a * (1.0 - e2) / (w * std::sqrt(w));  // M
  const double normal = a / std::sqrt(w);                        // N
  m_per_deg_lat_ = meridian * kRouteSubgoalsDeg;
  m_per_deg_lon_ = normal * std::cos(origin.latitude_deg * kRouteSubgoalsDeg) * kRouteSubgoalsDeg;
}

Vec2 LocalEnu::to_enu(const GeoPoint& p) const {
  return Vec2((p.lon_deg - origin_.longitude_deg) * m_per_deg_lon_, (p.lat_deg - origin_.latitude_deg) * m_per_deg_lat_);
}

GeoPoint LocalEnu::to_geo(const Vec2& enu) const {
  return GeoPoint{origin_.latitude_deg + enu.y() / m_per_deg_lat_, origin_.longitude_deg + enu.x() / m_per_deg_lon_};
}

namespace {
const ConfigKey<double> kSubroute{"planning.route.subroute_m", SubRouteConfig{}.subroute_m, {0.5, 1000.0},
                                  "length of one sub-route of a long route [m]"};
const ConfigKey<double> kRouteSubgoalsWindow{"planning.route.window_m", SubRouteConfig{}.window_m, {1.0, 200.0},
                                "side of the local map around the user for sub-route subgoals [m]"};
}  // namespace

ConfigSchema sub_route_config_schema() { return ConfigSchema().add(kSubroute).add(kRouteSubgoalsWindow); }

SubRouteConfig sub_route_config(const Config& config) {
  SubRouteConfig c;
  c.subroute_m = get(config, kSubroute);
  c.window_m = get(config, kRouteSubgoalsWindow);
  return c;
}

std::vector<SubRoute> cut_sub_routes(const std::vector<Vec2>& route_ENU, double subroute_m) {
  if (!(subroute_m > 0)) throw Error("cut_sub_routes: subroute_m must be > 0");
  std::vector<Vec2> pts;
  for (const Vec2& p : route_ENU) {
    if (pts.empty() || (p - pts.back()).norm() > 1e-9) pts.push_back(p);
  }
  std::vector<SubRoute> out;
  if (pts.size() < 2) return out;
  SubRoute current;
  current.points_ENU.push_back(pts[0]);
  double arc = 0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    Vec2 a = pts[i];
    const Vec2 b = pts[i + 1];
    double left = (b - a).norm();
    while (arc - current.start_m + left >= subroute_m - 1e-9) {
      const double step = subroute_m - (arc - current.start_m);
      const Vec2 cut = a + (b - a).normalized() * step;
      current.points_ENU.push_back(cut);
      arc += step;
      left -= step;
      current.end_m = arc;
      out.push_back(current);
      current = SubRoute{};
      current.start_m = arc;
      current.points_ENU.push_back(cut);
      a = cut;
      if (left <= 1e-9) break;
    }
    if (left > 1e-9) {
      arc += left;
      current.points_ENU.push_back(b);
    }
  }
  if (current.points_ENU.size() >= 2) {
    current.end_m = arc;
    if (!out.empty() && arc - current.start_m < 0.01 * subroute_m) {  // a sliver: part of the last piece
      out.back().points_ENU.insert(out.back().points_ENU.end(), current.points_ENU.begin() + 1, current.points_ENU.end());
      out.back().end_m = arc;
    } else {
      out.push_back(current);
    }
  }
  return out;
}

RouteSubgoal route_subgoal(const std::vector<SubRoute>& subroutes, const Vec2& user_ENU, double window_m) {
  if (subroutes.empty()) throw Error("route_subgoal: the route has no sub-routes");
  // The nearest sub-route and the nearest point on it (segment k, parameter t).
  RouteSubgoal out;
  double best = std::numeric_limits<double>::infinity();
  std::size_t seg = 0;
  double seg_t = 0;
  for (std::size_t s = 0; s < subroutes.size(); ++s) {
    const std::vector<Vec2>& p = subroutes[s].points_ENU;
    for (std::size_t k = 0; k + 1 < p.size(); ++k) {
      const double t = closest_t(p[k], p[k + 1], user_ENU);
      const double d = (p[k] + t * (p[k + 1] - p[k]) - user_ENU).norm();
      if (d < best - 1e-9) {
        best = d;
        out.subroute = s;
        seg = k;
        seg_t = t;
      }
    }
  }
  out.distance_to_route_m = best;
  out.subgoal.from_route = true;
  // Forward from there to the first point at the window's half-side from the user.
  const double radius = 0.5 * window_m;
  Vec2 from = subroutes[out.subroute].points_ENU[seg];
  from += seg_t * (subroutes[out.subroute].points_ENU[seg + 1] - from);
  for (std::size_t s = out.subroute; s < subroutes.size(); ++s) {
    const std::vector<Vec2>& p = subroutes[s].points_ENU;
    for (std::size_t k = (s == out.subroute ? seg : 0); k + 1 < p.size(); ++k) {
      const Vec2 a = (s == out.subroute && k == seg) ? from : p[k];
      const Vec2 b = p[k + 1];
      if ((a - user_ENU).norm() >= radius) {  // already outside (the user is off the route)
        out.subgoal.direction_rad = std::atan2(a.y() - user_ENU.y(), a.x() - user_ENU.x());
        return out;
      }
      if ((b - user_ENU).norm() >= radius) {  // the segment leaves the circle: solve |a + u d - p| = r
        const Vec2 d = b - a;
        const Vec2 f = a - user_ENU;
        const double qa = d.squaredNorm(), qb = 2 * f.dot(d), qc = f.squaredNorm() - radius * radius;
        const double u = (-qb + std::sqrt(std::max(0.0, qb * qb - 4 * qa * qc))) / (2 * qa);
        const Vec2 edge = a + std::clamp(u, 0.0, 1.0) * d;
        out.subgoal.direction_rad = std::atan2(edge.y() - user_ENU.y(), edge.x() - user_ENU.x());
        return out;
      }
    }
  }
  const Vec2 goal = subroutes.back().points_ENU.back();
  out.reaches_destination = true;
  out.subgoal.goal_W = goal;
  if ((goal - user_ENU).norm() > 1e-9) out.subgoal.direction_rad = std::atan2(goal.y() - user_ENU.y(), goal.x() - user_ENU.x());
  return out;
}

namespace {

Subgoal subgoal_in_world(const Subgoal& subgoal_ENU, double yaw, const Vec2& t) {
  const Eigen::Rotation2Dd inverse(-yaw);
  Subgoal w = subgoal_ENU;
  if (subgoal_ENU.goal_W) w.goal_W = inverse * (*subgoal_ENU.goal_W - t);
  if (subgoal_ENU.face_W) w.face_W = inverse * (*subgoal_ENU.face_W - t);
  if (subgoal_ENU.direction_rad) w.direction_rad = std::remainder(*subgoal_ENU.direction_rad - yaw, 2 * 3.14159265358979323846);
  return w;
}

}  // namespace

Subgoal subgoal_in_world(const Subgoal& subgoal_ENU, const SE3& T_ENU_W) {
  return subgoal_in_world(subgoal_ENU, yaw_of(T_ENU_W.q), T_ENU_W.t.head<2>());
}

}  // namespace navaid::planning
