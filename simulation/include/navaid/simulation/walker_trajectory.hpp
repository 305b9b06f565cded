#pragma once
// Continuous-time body trajectory of a pedestrian walking along a 2D polyline, with a human gait.
//
// Frames (DESIGN.md §4): W is gravity-aligned, z up. The body frame B has x forward (walking
// direction, plus head scanning), y left, z up. R_W_B = Rz(yaw) Ry(pitch) Rx(roll), where yaw is
// the path tangent heading plus the head scan, and pitch/roll are small gait oscillations.
//
// Construction: the polyline is densified (points every <= corner_spacing_m along each segment)
// and used as control points of a uniform quintic B-spline. Quintic (C^4) rather than cubic so
// that curvature and its derivative are continuous, which keeps the acceleration of the laterally
// swaying body continuous (a cubic made IMU integration lose ~1 mm in 10 s at its knots).
// Straight parts are reproduced exactly; corners are rounded over a few spacings and cut by at
// most 0.47 spacing. The spline is reparametrized by arc length (Gauss-Legendre quadrature +
// Newton inversion) and travelled at constant speed except for smooth quintic start/stop ramps
// (speed, acceleration and jerk continuous).
// All derivatives returned by state() are analytic (chain rule through the reparametrization).
#include <vector>

#include <Eigen/Core>

#include "navaid/core/geometry.hpp"

namespace navaid::simulation {

/// Pose and exact derivatives of the body B at one instant.
struct KinematicState {
  SE3 T_W_B;                      ///< body pose in W
  Vec3 v_W = Vec3::Zero();        ///< velocity of the body origin in W [m/s]
  Vec3 a_W = Vec3::Zero();        ///< acceleration of the body origin in W [m/s^2]
  Vec3 omega_B = Vec3::Zero();    ///< angular rate of B w.r.t. W, in B [rad/s]
  Vec3 alpha_B = Vec3::Zero();    ///< angular acceleration d(omega_B)/dt, in B [rad/s^2]
};

struct WalkerConfig {
  double speed_mps = 1.1;            ///< cruise walking speed along the path
  double ramp_time_s = 1.0;          ///< duration of each start/stop speed ramp (shortened on short paths)
  double mount_height_m = 1.7;       ///< body origin height above ground (head ~1.7, hand ~1.0)
  double ground_z_m = 0.0;           ///< z of the ground (waypoints are at this height)
  double corner_spacing_m = 0.5;     ///< densification spacing; sets the corner rounding
  double step_frequency_hz = 1.8;    ///< steps per second (vertical bob frequency)
  double bob_amplitude_m = 0.03;     ///< vertical bob amplitude
  double sway_amplitude_m = 0.025;   ///< lateral sway amplitude, at half the step frequency
  double pitch_amplitude_rad = 0.02; ///< gait nod amplitude, at the step frequency
  double roll_amplitude_rad = 0.02;  ///< gait roll amplitude, at half the step frequency
  double scan_amplitude_rad = 0.3;   ///< head yaw scanning amplitude (0 for cane/hand mounts)
  double scan_period_s = 4.0;        ///< head yaw scanning period
};

class WalkerTrajectory {
 public:
  /// waypoints: at least two distinct (x, y) points in W. Throws ConfigError on bad input.
  explicit WalkerTrajectory(const std::vector<Eigen::Vector2d>& waypoints, const WalkerConfig& config = {});

  /// State at time t [s] since the start. Before 0 and after duration() the walker stands still
  /// (gait off; the head scan continues).
  KinematicState state(double t) const;

  double duration() const { return duration_; }  ///< walking time including both ramps [s]
  double length() const { return length_; }      ///< arc length of the smoothed path [m]
  const WalkerConfig& config() const { return config_; }

  /// Point of the smoothed ground path at arc length s in [0, length()] (z = ground).
  Eigen::Vector2d path_point(double s) const;

 private:
  struct PathGeometry {  // everything about the ground curve at one arc length
    Eigen::Vector2d p, tangent, normal;  // normal = tangent rotated +90 deg (left)
    double kappa = 0, dkappa_ds = 0;     // signed curvature and its arc-length derivative
  };
  struct Profile {  // arc length s(t) and its first three time derivatives
    double s = 0, ds = 0, dds = 0, ddds = 0;
  };

  Profile profile(double t) const;
  PathGeometry geometry(double s) const;
  double span_arc_length(int span, double x) const;   // arc length from span start to local x
  double parameter_at(double s, int* span) const;     // local x in span for arc length s
  void spline_derivatives(int span, double x, Eigen::Vector2d d[4]) const;

  static constexpr int kDegree = 5;
  WalkerConfig config_;
  std::vector<Eigen::Vector2d> control_;  // B-spline control points incl. phantom end points
  std::vector<double> span_start_s_;      // arc length at the start of each span (+ total)
  double length_ = 0, duration_ = 0, ramp_ = 0;
};

}  // namespace navaid::simulation
