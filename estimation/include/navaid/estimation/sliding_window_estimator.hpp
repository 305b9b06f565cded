#pragma once
// Sliding-window visual-inertial estimator on feature-level input (W-ROMA RGBD-VIO §V-B,
// VINS-Mono's window management). docs/estimator.md, "Sliding window", says what it does, step
// by step; the short version:
//
//  - Initialization: the recording starts standing still. At the first feature frame with
//    still_duration_s of IMU data before it, gravity comes from the mean accelerometer, velocity
//    and biases are zero and yaw is 0: the estimate's W frame differs from any ground-truth world
//    frame by a 4-DOF transform (yaw + translation). (A full visual-inertial initialization, which
//    does not need a still start, is a later issue.)
//  - Every feature frame gets a state (pose, velocity, biases) propagated by IMU preintegration
//    from the newest keyframe, and the window (keyframes + this frame) is solved by Ceres. The
//    frame becomes a keyframe when the mean parallax to the last keyframe reaches the threshold,
//    when too few tracks are shared with it, or after keyframe_max_interval_s; otherwise it is
//    dropped after its solve (VINS drops the second-newest non-keyframe the same way).
//  - When the window holds more than window_size keyframes the oldest is marginalized into a prior
//    (Marginalizer), or, with marginalization off, dropped with a tight prior holding the gauge on
//    the new oldest keyframe.
//  - GPS (factors.gps), gps.mode "joint": fixes are registered against the VIO track (eLabrador
//    eq. 6-7, gps_registration.hpp) to initialize T_ENU_W; from then on T_ENU_W is a window block
//    and each fix a GpsPositionFactor on the frame taken with it. "decoupled" (eLabrador): no GPS
//    in the window; at every fix T_ENU_W is re-registered over the fixes so far (or the newest
//    gps.registration_fixes) and reported with the registration's covariance.
//  - Magnetometer (factors.mag): each state gets the calibrated field at its time (interpolated
//    between the bracketing samples) as a MagnetometerYawFactor. Its alignment block is T_ENU_W
//    when that is in the window (joint GPS, registered); otherwise psi, the heading of W from
//    magnetic north, a window block started from the still start's mean field (without GPS the
//    factor thus bounds the yaw drift relative to the start).
//  - Output: a StateEstimate for every feature frame, with the covariance of the newest state (and
//    of T_ENU_W) from the window's information (prior included), in StateEstimate's parametrization.
//
// Events must come in time order (io::SensorEventStream). A frame is processed once the IMU has
// passed its time (the IMU sample after it is needed to interpolate), so estimates come out with
// a delay of one IMU sample. Single-threaded and deterministic: the same events and configuration
// give the same estimates bit for bit.
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/estimator_config.hpp"

namespace navaid::estimation {

/// Whitened residuals of one factor type after the solves (estimator.diagnostics.residuals): for a
/// noise model that matches the data, squared_sum / rows is a little below 1 (the fit absorbs
/// the parameters' share); far above 1 means the factor's covariance is too small.
struct ResidualStatistics {
  std::size_t factors = 0;   ///< residual blocks evaluated, summed over solves
  std::size_t rows = 0;      ///< residual rows (degrees of freedom), summed over solves
  double squared_sum = 0;    ///< sum of |r|^2 (before the robust loss)
  std::size_t beyond_3_sigma_rms = 0;  ///< blocks with |r|^2 / rows > 9
};

/// Where one frame's estimator time went (steady clock: measured, not part of the deterministic
/// output). Frames that were not solved (initializing, lost at the end) have zeros.
struct FrameStageTimes {
  bool keyframe = false;
  double solve_ms = 0;            ///< the window's (or the newest state's) residuals, problem and Ceres solve
  double covariance_ms = 0;       ///< the newest state's covariance
  double marginalization_ms = 0;  ///< the oldest keyframe out of the window (keyframes only)
};

struct EstimatorStatistics {
  std::size_t frames = 0;            ///< feature frames estimated (every mode)
  std::size_t keyframes = 0;         ///< frames kept as keyframes
  std::size_t solves = 0;
  std::size_t solver_iterations = 0;  ///< Levenberg-Marquardt iterations over all solves
  /// Solves stopped by estimator.solver.max_iterations before they converged (a cap that cuts
  /// solves short leaves errors the next frames inherit: raise it, or look at why).
  std::size_t solves_at_iteration_cap = 0;
  std::size_t marginalizations = 0;
  std::size_t marginalization_failures = 0;  ///< prior dropped, gauge pinned instead
  /// Tracks whose anchor keyframe left while they were alive and that kept their landmark in the
  /// prior (estimator.features.leaving_anchor = hand_over).
  std::size_t handed_over_tracks = 0;
  /// joint: 1 once T_ENU_W was initialized from the fixes; decoupled: successful registrations
  std::size_t gps_registrations = 0;
  std::size_t covariance_failures = 0;  ///< covariance could not be computed (previous one inflated)
  std::size_t features_in_last_solve = 0;
  std::size_t depth_features_in_last_solve = 0;
  /// Visual-inertial initialization (initialization.method hpnp / pnp): attempts that failed, and
  /// the reason of the last failure.
  std::size_t initialization_attempts = 0;
  std::size_t initialization_failures = 0;
  std::string last_initialization_failure;
  double initialized_at_s = -1;  ///< IMU-clock time of the (latest) initialization [s] (-1: not yet)
  /// Still initializations that took the gyro bias from a still window the camera confirmed.
  std::size_t still_gyro_bias_initializations = 0;
  /// Frames that got a zero-velocity update (their tracks stood still).
  std::size_t zero_velocity_frames = 0;
  /// Frames whose IMU-clock time (camera stamp + the time offset estimated so far) was not after
  /// the newest state's: a camera clock that jumped back, with the offset still moving. Their
  /// observations are dropped; their estimate is the newest state's.
  std::size_t frames_out_of_time_order = 0;
  /// States whose magnetometer field failed the disturbance test (strength or inclination off
  /// the reference's: estimator.mag.max_norm_deviation, max_inclination_deviation).
  std::size_t mag_disturbed = 0;
  /// GPS fixes not used: too far from the registered state's prediction (estimator.gps.outlier_gate).
  std::size_t gps_outliers = 0;
  /// Failure detection (estimator.failure.*): solves found implausible, the last reason (with its
  /// time), window restarts from the last good estimate (map frame kept) and re-initializations
  /// in a new map frame (W moved: consumers must drop what they built in the old one).
  std::size_t failures = 0;
  std::string last_failure;
  std::size_t restarts = 0;
  std::size_t map_frame_resets = 0;
  /// Per factor type ("imu", "reprojection", "depth_3d", "inverse_depth", "prior", "gps", ...),
  /// filled only with estimator.diagnostics.residuals.
  std::map<std::string, ResidualStatistics> residuals;
};

class SlidingWindowEstimator {
 public:
  /// Needs the rig's camera `camera_name` (the first camera when empty) and IMU calibration;
  /// throws ConfigError when either is missing or unusable, when depth factors are on and the
  /// camera has no depth noise model (baseline, disparity sigma) and the config gives none, or
  /// when GPS factors are on without the geodetic origin of the ENU frame.
  SlidingWindowEstimator(const RigCalibration& rig, const EstimatorConfig& config,
                         const std::string& camera_name = {},
                         const std::optional<GeodeticOrigin>& origin = std::nullopt);
  ~SlidingWindowEstimator();
  /// Copies the whole window (the benchmark re-solves one window many times).
  SlidingWindowEstimator(const SlidingWindowEstimator& other);
  SlidingWindowEstimator& operator=(const SlidingWindowEstimator&) = delete;
  SlidingWindowEstimator(SlidingWindowEstimator&&) noexcept;
  SlidingWindowEstimator& operator=(SlidingWindowEstimator&&) noexcept;

  /// Feeds one event and returns the estimates that became ready (feature frames whose time the
  /// IMU has now passed). GPS fixes are used when the gps factor is on, magnetometer samples
  /// (in the IMU clock, like the fixes) when the mag factor is on; an RgbdFrame
  /// throws Error (the image front end does not exist yet). Throws Error on events out of time
  /// order or IMU samples without gyro data.
  std::vector<StateEstimate> process(const SensorEvent& event);
  /// Estimates for frames still waiting for IMU data at the end of a recording: no IMU data covers
  /// them, so they repeat the last estimate's state, in mode "lost".
  std::vector<StateEstimate> finish();

  /// Solves the current window again (benchmarks, tests); returns the number of visual features used.
  std::size_t optimize();

  const EstimatorConfig& config() const;
  /// The camera-IMU extrinsic T_B_C in use: the calibration's, or the online estimate
  /// (estimator.extrinsic.estimate).
  SE3 camera_extrinsic() const;
  /// The camera-IMU time offset td in use, t_imu = t_cam + td [s]: the calibration's, or the online
  /// estimate (estimator.time_offset.estimate).
  double camera_time_offset_s() const;
  const EstimatorStatistics& statistics() const;
  /// One per estimate returned by the last process() or finish() call, in the same order.
  const std::vector<FrameStageTimes>& stage_times() const;
  /// Keyframes currently in the window.
  std::size_t window_keyframes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::estimation
