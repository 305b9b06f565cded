#pragma once
// W-ROMA's hand-movement rule (seed w-roma-rgbd-vio-object-manipulation, Sec. IV): from the
// target object's centre P = [X_h, Y_h, Z_h] in the hand frame H, pick the motor command.
//
//   - Z_h <= 0: "backward" (the object is behind the hand's plane).
//   - Z_h > 0 and the hand aligned with the object: "forward". The paper reports Z_h and says
//     the projection decides the lateral movement but gives no alignment radius; ours: aligned
//     when the lateral offset r = sqrt(X_h^2 + Y_h^2) <= max(aligned_radius_m,
//     Z_h * tan(aligned_angle)). Near the object the metric radius rules (a hand closes around a
//     5 cm offset); far away the cone does (a 5 deg bearing error is what a user can hold while
//     walking, and it shrinks to centimetres on the way in).
//   - otherwise one of 8 sectors of 45 deg by the angle of the projection P~ = (X_h, Y_h) on the
//     virtual image plane.
//
// Frame H and the angle (our reading of the paper, written down once here):
//   H has the camera's optical axes (core/camera.hpp): X_h right, Y_h down in the image, Z_h
//   forward along the optical axis; its origin is the hand (for the hand-held Structure Core the
//   image centre, Fig. 4d), so T_H_C is a translation for a rigid grip. The sector angle is the
//   angle of P~ as the user sees the image: theta = atan2(-Y_h, X_h), 0 = right, +90 deg = up
//   (counter-clockwise on the displayed image). That is the convention in which the paper's
//   example holds: P~ to the lower left (X_h < 0, Y_h > 0) has theta in [-157.5, -112.5] deg and
//   the command "down left".
//   Sectors, each [lower, upper) counter-clockwise: right [-22.5, 22.5), up-right [22.5, 67.5),
//   up [67.5, 112.5), up-left [112.5, 157.5), left [157.5, 180] U [-180, -157.5), down-left
//   [-157.5, -112.5), down [-112.5, -67.5), down-right [-67.5, -22.5). A boundary belongs to the
//   sector counter-clockwise of it; angles within 1e-9 of a sector width below a boundary count
//   as on it, so a boundary given in degrees stays on its side after the round trip to radians.
#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::planning {

struct HandSectorConfig {
  double aligned_radius_m = 0.05;              ///< lateral offset counted as aligned near the object
  double aligned_angle_rad = 0.0872664626;     ///< 5 deg: the aligned cone far away
  double reach_distance_m = 0.15;              ///< aligned and nearer than this: the hand is at the object
};

/// Keys planning.hand.aligned_radius_m [0.005, 1], planning.hand.aligned_angle_deg [0.1, 45],
/// planning.hand.reach_distance_m [0, 1]; ConfigError when out of range.
HandSectorConfig read_hand_sector_config(const Config& config);

/// theta = atan2(-Y_h, X_h) in (-pi, pi]: 0 right, +pi/2 up on the image plane.
double image_plane_angle(const Vec3& P_H);

/// The sector of an image-plane angle [rad] (any value; wrapped). One of the 8 lateral directions.
HandDirection sector_of_angle(double theta_rad);

/// True when the lateral offset is within the aligned radius / cone (needs Z_h > 0).
bool hand_aligned(const Vec3& P_H, const HandSectorConfig& config);

/// The paper's rule: kBackward for Z_h <= 0, kForward when aligned, else the sector of P~.
/// Non-finite P_H gives kHold.
HandDirection hand_direction(const Vec3& P_H, const HandSectorConfig& config);

/// The same rule on a bearing only (case II, no depth): aligned when the angle between the ray
/// and the optical axis is within aligned_angle (the metric radius needs a distance).
HandDirection hand_direction_of_bearing(const Vec3& ray_H, const HandSectorConfig& config);

}  // namespace navaid::planning
