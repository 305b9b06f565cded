#pragma once
// What the user asks the device for, beside its preset: where to walk or what to reach. A real
// device hears it from its user (a voice command, a destination typed on the phone); a replay
// or a closed-loop trial says it for the user. Which member a chain reads: route (kRoute),
// walking_goal (kWalkingPath, unless device.goal_start_frame_m gives it), tag_id (kHandTarget,
// unless device.tag_id gives it).
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "navaid/core/calibration.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/core/time.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/osm_foot_graph.hpp"

namespace navaid::runtime {

/// eLabrador: a walk over a street map from a start to a destination.
struct RouteMission {
  planning::FootGraph streets;
  std::string streets_name;  ///< where the streets came from, for messages (an OSM file)
  planning::GeoPoint from, to;
  std::optional<planning::GeoPoint> face;  ///< the landmark to face on arrival
  GeodeticOrigin origin;                   ///< the estimator's ENU origin
};

/// Smart Cane: the goal as the user gives it when guidance starts (at the first localised
/// estimate, time t): forward and left of where they stand [m].
using WalkingGoal = std::function<std::pair<double, double>(Timestamp t)>;

struct DeviceMission;

/// The mission "go to <place>" asks for, from where the device believes the user is (`now`, the
/// estimate the command is handled at); nullopt for a place the device does not know.
using PlaceResolver = std::function<std::optional<DeviceMission>(std::string_view place, const StateEstimate& now)>;

struct DeviceMission {
  std::optional<RouteMission> route;
  WalkingGoal walking_goal;
  std::optional<int> tag_id;  ///< W-ROMA: the AprilTag on the object to reach
  /// The places the user may name by voice (empty: "go to" is not understood).
  PlaceResolver place;
};

/// Where the estimate puts the user on the map: its position through the GPS-map registration
/// T_ENU_W, in latitude and longitude about `origin`; nullopt before the registration (a route
/// from here waits for it).
std::optional<planning::GeoPoint> geodetic_position(const StateEstimate& estimate, const GeodeticOrigin& origin);

/// "go to <place>" on a route's streets: their named landmarks (OSM name=*; matched without
/// regard to case or repeated spaces), routed from where the estimate puts the user (the route's
/// start before the GPS-map registration) and facing the landmark on arrival.
PlaceResolver street_places(RouteMission streets);

}  // namespace navaid::runtime
