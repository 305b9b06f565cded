#pragma once
// eLabrador §III-C: the walking route is cut into short sub-routes; from the user's position the
// nearest sub-route gives the local planner a directional subgoal at the local map's edge.
//
// Frames: the route is mapped into a local ENU frame (x east, y north) at a GeodeticOrigin, which
// must be the origin of the GPS-map registration (estimation/gps_registration.hpp) when the subgoal
// is handed to the estimator's W frame. Geodetic -> ENU uses the WGS84 radii of curvature at the
// origin (cm-accurate within ~1 km of it).
#include <cstddef>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/path_guidance.hpp"

namespace navaid::planning {

/// Geodetic <-> local ENU (metres) about an origin.
class LocalEnu {
 public:
  explicit LocalEnu(const GeodeticOrigin& origin);
  Vec2 to_enu(const GeoPoint& p) const;
  GeoPoint to_geo(const Vec2& enu) const;
  const GeodeticOrigin& origin() const { return origin_; }

 private:
  GeodeticOrigin origin_;
  double m_per_deg_lat_ = 0, m_per_deg_lon_ = 0;
};

struct SubRouteConfig {
  double subroute_m = 10.0;  ///< planning.route.subroute_m: length of one sub-route
  double window_m = 10.0;    ///< planning.route.window_m: side of the local map, centred on the user
};
SubRouteConfig sub_route_config(const Config& config);

struct SubRoute {
  std::vector<Vec2> points_ENU;  ///< >= 2 points
  double start_m = 0, end_m = 0; ///< arc length along the whole route
};

/// Cuts a polyline (ENU) into consecutive pieces of subroute_m (the last one shorter; a last sliver
/// under 1 % of subroute_m joins the piece before); pieces share their end points. Fewer than 2 distinct points: no sub-routes.
std::vector<SubRoute> cut_sub_routes(const std::vector<Vec2>& route_ENU, double subroute_m);

struct RouteSubgoal {
  Subgoal subgoal;                 ///< in ENU; from_route = true
  std::size_t subroute = 0;        ///< index of the nearest sub-route
  double distance_to_route_m = 0;  ///< user to the nearest sub-route
  bool reaches_destination = false;///< the destination lies inside the window: goal_W = destination
};

/// The eLabrador rule. From the nearest point of the nearest sub-route, walk forward along the route
/// to the first point at window_m / 2 from the user (the local map's edge): the subgoal heading
/// (radians from +x = east, counter-clockwise) points there. When the route ends inside the window the
/// subgoal is the destination itself (goal_W and its heading). Throws Error on no sub-routes.
RouteSubgoal route_subgoal(const std::vector<SubRoute>& subroutes, const Vec2& user_ENU, double window_m);

/// Maps an ENU subgoal into W through the GPS-map registration T_ENU_W (a StateEstimate's, 4-DOF:
/// its yaw and translation): goal_W = Rz(-yaw) (goal_ENU - t), heading_W = heading_ENU - yaw.
Subgoal subgoal_in_world(const Subgoal& subgoal_ENU, const SE3& T_ENU_W);

}  // namespace navaid::planning
