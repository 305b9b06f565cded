#include "navaid/runtime/device_mission.hpp"

#include <cctype>
#include <memory>

#include "navaid/planning/route_subgoals.hpp"

namespace navaid::runtime {

namespace {

/// Lower case, single spaces, trimmed: how a place is said and how the map spells it compare.
std::string normalized(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isspace(c)) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::tolower(c));
    }
  }
  if (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

/// A resolver that hands each new mission itself, so that the user may name another place later.
struct StreetPlaces {
  std::shared_ptr<const RouteMission> streets;

  std::optional<DeviceMission> operator()(std::string_view place, const StateEstimate& now) const {
    const std::string wanted = normalized(place);
    for (const planning::Landmark& landmark : streets->streets.landmarks) {
      if (landmark.name.empty() || normalized(landmark.name) != wanted) continue;
      RouteMission route = *streets;
      route.from = geodetic_position(now, route.origin).value_or(streets->from);
      route.to = planning::GeoPoint{landmark.lat_deg, landmark.lon_deg};
      route.face = route.to;
      DeviceMission mission;
      mission.route = std::move(route);
      mission.place = *this;
      return mission;
    }
    return std::nullopt;
  }
};

}  // namespace

std::optional<planning::GeoPoint> geodetic_position(const StateEstimate& estimate, const GeodeticOrigin& origin) {
  if (!estimate.T_ENU_W) return std::nullopt;
  const Vec3 p_ENU = *estimate.T_ENU_W * estimate.T_W_B.t;
  return planning::LocalEnu(origin).to_geo(p_ENU.head<2>());
}

PlaceResolver street_places(RouteMission streets) {
  return StreetPlaces{std::make_shared<const RouteMission>(std::move(streets))};
}

}  // namespace navaid::runtime
