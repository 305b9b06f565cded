#include "navaid/runtime/device_mission.hpp"

#include "navaid/planning/route_subgoals.hpp"

namespace navaid::runtime {

std::optional<planning::GeoPoint> geodetic_position(const StateEstimate& estimate, const GeodeticOrigin& origin) {
  if (!estimate.T_ENU_W) return std::nullopt;
  const Vec3 p_ENU = *estimate.T_ENU_W * estimate.T_W_B.t;
  return planning::LocalEnu(origin).to_geo(p_ENU.head<2>());
}

}  // namespace navaid::runtime
