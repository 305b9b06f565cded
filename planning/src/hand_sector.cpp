#include "navaid/planning/hand_sector.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {
const ConfigKey<double> kAlignedRadius{"planning.hand.aligned_radius_m", HandSectorConfig{}.aligned_radius_m,
                                       {0.005, 1.0}, "lateral offset counted as aligned near the object [m]"};
const ConfigKey<double> kAlignedAngle{"planning.hand.aligned_angle_deg", rad_to_deg(HandSectorConfig{}.aligned_angle_rad),
                                      {0.1, 45.0}, "half-angle of the aligned cone far from the object [deg]"};
const ConfigKey<double> kReachDistance{"planning.hand.reach_distance_m", HandSectorConfig{}.reach_distance_m,
                                       {0.0, 1.0}, "aligned and nearer than this: the hand is at the object [m]"};
}  // namespace

ConfigSchema hand_sector_config_schema() { return ConfigSchema().add(kAlignedRadius).add(kAlignedAngle).add(kReachDistance); }

HandSectorConfig read_hand_sector_config(const Config& config) {
  HandSectorConfig c;
  c.aligned_radius_m = get(config, kAlignedRadius);
  c.aligned_angle_rad = deg_to_rad(get(config, kAlignedAngle));
  c.reach_distance_m = get(config, kReachDistance);
  return c;
}

double image_plane_angle(const Vec3& P_H) { return std::atan2(-P_H.y(), P_H.x()); }

HandDirection sector_of_angle(double theta_rad) {
  // Counter-clockwise from "right", each sector centred on a multiple of 45 deg.
  static constexpr std::array<HandDirection, 8> kSectors = {
      HandDirection::kRight, HandDirection::kUpRight,  HandDirection::kUp,   HandDirection::kUpLeft,
      HandDirection::kLeft,  HandDirection::kDownLeft, HandDirection::kDown, HandDirection::kDownRight};
  const double width = kPi / 4.0;
  const double s = (theta_rad + width / 2.0) / width;
  const double k = std::floor(s + 1e-9);
  const long index = static_cast<long>(k) % 8;
  return kSectors[static_cast<std::size_t>(index < 0 ? index + 8 : index)];
}

bool hand_aligned(const Vec3& P_H, const HandSectorConfig& config) {
  if (!(P_H.z() > 0.0)) return false;
  const double r = P_H.head<2>().norm();
  return r <= std::max(config.aligned_radius_m, P_H.z() * std::tan(config.aligned_angle_rad));
}

HandDirection hand_direction(const Vec3& P_H, const HandSectorConfig& config) {
  if (!P_H.allFinite()) return HandDirection::kHold;
  if (P_H.z() <= 0.0) return HandDirection::kBackward;
  if (hand_aligned(P_H, config)) return HandDirection::kForward;
  return sector_of_angle(image_plane_angle(P_H));
}

HandDirection hand_direction_of_bearing(const Vec3& ray_H, const HandSectorConfig& config) {
  if (!ray_H.allFinite() || ray_H.norm() == 0.0) return HandDirection::kHold;
  if (ray_H.z() <= 0.0) return HandDirection::kBackward;
  const double off_axis = std::atan2(ray_H.head<2>().norm(), ray_H.z());
  if (off_axis <= config.aligned_angle_rad) return HandDirection::kForward;
  return sector_of_angle(image_plane_angle(ray_H));
}

}  // namespace navaid::planning
