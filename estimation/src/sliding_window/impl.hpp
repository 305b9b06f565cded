#pragma once
// Private to the sliding-window estimator (sliding_window_estimator.cpp and the files of
// src/sliding_window/): the window's state records, tuning constants and the Impl that the public
// class hides. Not installed, not included by anything else.
#include <ceres/ceres.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <string>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/estimation/estimator_config.hpp"
#include "navaid/estimation/failure_detection.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/feature_track_store.hpp"
#include "navaid/estimation/gps_registration.hpp"
#include "navaid/estimation/imu_preintegration.hpp"
#include "navaid/estimation/marginalization.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/estimation/state_prior_factor.hpp"

namespace navaid::estimation::sliding_window {


// Re-integrate a preintegration when the bias estimate left its linearization point this far
// (the first-order correction is good well beyond; VINS uses similar values).
inline constexpr double kRepropagateGyro = 5e-3;   // [rad/s]
inline constexpr double kRepropagateAccel = 5e-2;  // [m/s^2]
// Feature depths outside this range after a solve are failures (VINS-Mono removes them too).
inline constexpr double kMinFeatureDepth = 0.05;  // [m]
inline constexpr double kMaxFeatureDepth = 500.0;
// Triangulation needs this much angle between the extreme rays.
inline constexpr double kMinTriangulationAngle = 1.0 * M_PI / 180.0;
// Gauge prior of the first state (position and yaw define W) and, with marginalization off, of
// the oldest keyframe that holds the window in place.
inline constexpr double kGaugeSigma = 1e-3;
inline constexpr double kPinnedPoseSigma = 1e-4;
inline constexpr double kLooseSpeedBiasSigma = 1e2;
// Covariance with covariance_weights = inliers: a visual residual block with |r|^2 above this
// (about the 99.9 % point of a chi-square with 2 or 3 degrees of freedom) is left out.
inline constexpr double kCovarianceGate = 16.0;
// Covariance reported before initialization (nothing is known).
inline constexpr double kUnknownVariance = 1e4;
// Height offset of T_ENU_W when the registration had no fix heights [m].
inline constexpr double kUnregisteredHeightSigma = 100.0;
// Prior of the magnetic heading of W: only a starting point (the first samples' heading depends
// on the still start's roll and pitch, which the accelerometer bias tilts: a fixed reference
// measured 0.025 rad of yaw error on lab-walk-1), and of its unused translation part.
inline constexpr double kMagHeadingPriorSigma = 1.0;  // [rad]
inline constexpr double kMagUnusedPriorSigma = 1.0;
// Tracks two frames must share before their image motion says whether the camera stood still.
inline constexpr std::size_t kMinStillTracks = 10;
// A still start's accelerometer mean must be this close to gravity's magnitude [m/s^2] for a
// re-initialization to use it (a walking user's mean is not gravity).
inline constexpr double kStillGravityTolerance = 0.3;
// The gyro-bias standard error of a still window: the sample standard deviation over sqrt(n),
// times this for the vibration's correlation between samples.
inline constexpr double kStillBiasErrorFactor = 2.0;
// Iterations of a restarted window's solves (failure_recovery.cpp): small problems, far first guesses.
inline constexpr int kRestartMaxIterations = 50;

// The gyro over a stretch the camera saw still: its mean is the bias, to within sigma.
struct StillGyro {
  Vec3 mean = Vec3::Zero();
  Vec3 sigma = Vec3::Zero();
};

struct WindowState {
  std::uint64_t id = 0;
  Timestamp t = 0;  // IMU clock
  double pose[kPoseSize] = {0, 0, 0, 0, 0, 0, 1};
  double speed_bias[kSpeedBiasSize] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  bool keyframe = false;
  std::optional<StillGyro> still;  // its tracks stood still: a zero-velocity update holds v = 0, b_g = mean
  std::optional<ImuPreintegration> imu;  // from the previous state of the window
  std::optional<GpsFix> gps;             // a fix taken at this state's time (within half a frame)
  std::optional<Vec3> mag_B;             // calibrated field at this state's time
  bool mag_decided = false;              // the samples around t have arrived (mag_B set or none usable)
  // Joint GPS with multipath (gps.multipath_fraction > 0): the fix's bias b (ENU), a Gauss-Markov
  // process linked to the previous fix's bias while that is in the window, or started from its
  // stationary prior N(0, multipath covariance) when the chain has no predecessor.
  bool has_gps_bias = false;
  double gps_bias[3] = {0, 0, 0};
  Mat3 gps_multipath_covariance = Mat3::Zero();
  std::optional<std::uint64_t> gps_bias_previous;
  std::shared_ptr<MarginalizationPrior> gps_bias_prior;

  SE3 T_W_B() const { return pose_from_block(pose); }
  Vec3 v() const { return Vec3(speed_bias[0], speed_bias[1], speed_bias[2]); }
  Vec3 b_g() const { return Vec3(speed_bias[3], speed_bias[4], speed_bias[5]); }
  Vec3 b_a() const { return Vec3(speed_bias[6], speed_bias[7], speed_bias[8]); }
};

struct Residual {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;
  std::vector<double*> blocks;
  /// The residual diagnostics' type when the factor's class does not say it (a far feature's weak
  /// depth prior is an inverse-depth factor, but not a measurement at its noise model).
  const char* diagnostic_type = nullptr;
};

struct NewestCovariance {
  Mat15 state;
  std::optional<Mat4> enu_alignment;  // [yaw, t_x, t_y, t_z] when T_ENU_W is in the window
};

struct VisualCount {
  std::size_t features = 0;        // tracks with factors that the newest frame observes
  std::size_t depth_features = 0;  // ... of which with a depth factor
  std::size_t all_features = 0;    // tracks with factors in the window
  bool solver_failed = false;      // Ceres ended in FAILURE (the state is whatever it reached)
  // Visual residual blocks on the newest frame after the solve, and those inside the covariance's
  // inlier gate: when vision and the IMU disagree, the solve leaves most of them outside.
  VisualSupport newest;
};

}  // namespace navaid::estimation::sliding_window

namespace navaid::estimation {

using namespace sliding_window;  // private header of one class

struct SlidingWindowEstimator::Impl {
  EstimatorConfig cfg;
  CameraCalibration camera;
  std::shared_ptr<const CameraModel> camera_model;
  ImuNoise imu_noise;
  double focal_px = 0;
  double sigma_lambda = 0;  // 0: no depth noise model (depth factors unusable)
  Timestamp camera_to_imu_ns = 0;
  double extrinsic[kPoseSize];
  // Online camera-IMU calibration (estimator.extrinsic.estimate): the calibration's T_B_C as a
  // Gaussian prior on the extrinsic block, which is otherwise held constant.
  std::shared_ptr<MarginalizationPrior> extrinsic_prior;
  // Online camera-IMU time offset (estimator.time_offset.estimate): td [s], t_imu = t_cam + td,
  // started from the calibration with a Gaussian prior; new frames are placed with the current
  // estimate (camera_to_imu_ns follows it).
  double time_offset[1] = {0};
  std::shared_ptr<MarginalizationPrior> time_offset_prior;
  // The previous frame's observation of each track (velocities for the time offset).
  struct LastSeen {
    Timestamp t;
    Eigen::Vector2d m;
    std::optional<double> depth_m;
  };
  std::unordered_map<std::uint64_t, LastSeen> last_seen;
  // The visual factors' loss: a wrapper around the robust loss (null without one), which the
  // covariance switches to the inlier gate (covariance_weights: inliers) while it evaluates.
  std::shared_ptr<ceres::LossFunctionWrapper> loss;
  std::shared_ptr<ceres::LossFunction> robust_loss;

  // GPS: fixes wait for the frame nearest to them; T_ENU_W = [yaw, t] joins the window once the
  // eLabrador registration of the first fixes against the VIO track succeeds.
  std::optional<GeodeticOrigin> origin;
  Vec3 gps_lever_arm_B = Vec3::Zero();
  std::shared_ptr<ceres::LossFunction> gps_loss;
  std::deque<GpsFix> pending_fixes;
  std::vector<GpsRegistrationPair> registration_pairs;
  bool enu_registered = false;
  double enu_alignment[kEnuAlignmentSize] = {0, 0, 0, 0};
  std::shared_ptr<MarginalizationPrior> enu_prior;  // the registration's estimate and covariance
  std::optional<std::uint64_t> last_gps_bias_state;  // newest state with a multipath bias
  // Decoupled GPS: the latest registration over the fixes (T_ENU_W outside the window).
  std::optional<SE3> decoupled_T_ENU_W;
  Mat4 decoupled_covariance = Mat4::Zero();

  // Magnetometer: calibrated samples; the factors tie each state's heading to magnetic north
  // through T_ENU_W when it is in the window (joint GPS, registered), otherwise through
  // mag_alignment = [psi, 0, 0, 0]: psi, the heading of W from magnetic north, is a window block
  // started from the first samples, with a weak prior (the translation part is unused, held at 0).
  std::deque<MagSample> mag;
  double mag_sigma_yaw = 0;
  bool mag_referenced = false;
  double mag_alignment[kEnuAlignmentSize] = {0, 0, 0, 0};
  std::optional<Timestamp> mag_heading_off_since;  ///< first state whose field heading disagreed
  std::optional<Timestamp> gps_outlier_since;      ///< first fix of the current run of gated fixes
  std::shared_ptr<MarginalizationPrior> mag_prior;

  // The poses' manifold, for the solve's problem and the covariance's tangent-space Jacobians.
  std::shared_ptr<ceres::Manifold> pose_manifold{make_pose_manifold()};
  std::deque<std::unique_ptr<WindowState>> window;  // oldest first; addresses stay put
  FeatureTrackStore tracks;
  std::vector<ImuSample> imu;
  std::deque<FeatureFrame> pending;
  // The frames of the last still_duration / zero-velocity look-back, for the stillness tests.
  std::deque<FeatureFrame> recent_frames;
  // Landmark blocks of the tracks first initialized for the frame being solved.
  std::unordered_set<const double*> fresh_landmarks;
  /// The camera stood still (image_motion.hpp) over `span_s` before `frame` (IMU time t): the
  /// gyro's mean and its error over that span (the samples' spread over sqrt(n), never below white
  /// noise, and the turn the image saw); none when the camera moved or the IMU does not cover it.
  std::optional<StillGyro> still_gyro(const FeatureFrame& frame, Timestamp t, double span_s, double max_px) const;
  /// A still start can (re-)initialize at `frame` (IMU time t): the camera stood still over the
  /// still window and the mean specific force there is gravity's magnitude.
  bool still_start_possible(const FeatureFrame& frame, Timestamp t) const;
  std::shared_ptr<MarginalizationPrior> marginal_prior;
  std::shared_ptr<StatePriorFactor> state_prior;
  std::uint64_t state_prior_id = 0;
  std::uint64_t next_id = 0;
  bool initialized = false;
  // The method of the next initialization: the configured one, hpnp for a re-initialization of a
  // still start (the user is not standing still then).
  InitializationMethod init_method = InitializationMethod::kStill;
  bool restarting = false;  // solving the frame of a failure again, from the restarted window
  // Solves left without the robust loss after a restart: the loss presumes a good first guess,
  // which the restarted window's velocity is not.
  int gaussian_solves = 0;
  // Estimates vision confirmed (failure.*), the newest restart_max_gap_s + the restart's back-off.
  std::deque<StateEstimate> confirmed;
  void confirm(const StateEstimate& e);
  // Inlier shares of the last second's frames (those with enough visual residual blocks).
  std::deque<std::pair<Timestamp, double>> inlier_shares;
  /// Sets support.recent_median from the shares, then adds this frame's.
  void record_inlier_share(Timestamp t, VisualSupport& support);
  Timestamp last_event_t = std::numeric_limits<Timestamp>::min();
  std::optional<Timestamp> imu_only_since;
  std::optional<StateEstimate> last_estimate;
  EstimatorStatistics stats;
  std::vector<FrameStageTimes> stage_times;  // per estimate of the last process() / finish()
  FrameStageTimes frame_stages;              // the frame being handled

  Impl(const RigCalibration& rig, const EstimatorConfig& config, const std::string& camera_name,
       const std::optional<GeodeticOrigin>& geodetic_origin);
  void attach_gps(WindowState& s);
  /// The innovation gate: whether a fix is to be left out (counts and times the run of them).
  bool gps_outlier(const GpsFix& fix, const WindowState& s);
  void start_gps_bias(WindowState& s);
  void register_gps(const WindowState& s);
  /// T_ENU_W's Gaussian prior from a covariance of [yaw, t] (false when not positive definite).
  bool set_enu_prior(const Mat4& covariance);
  void reregister_gps(const WindowState& s);
  GpsRegistration registration(const std::vector<GpsRegistrationPair>& pairs) const;
  void attach_mag(WindowState& s);
  /// The disturbance test of estimator.mag.max_norm_deviation / max_inclination_deviation.
  bool magnetically_disturbed(const Vec3& field_B, const WindowState& s);
  void set_mag_reference(const Vec3& field_B, const SE3& T_W_B);
  double* mag_alignment_block() { return enu_registered ? enu_alignment : mag_alignment; }
  Vec3 fix_enu(const GpsFix& fix) const;
  Impl(const Impl& other);

  std::vector<StateEstimate> process(const SensorEvent& event);
  StateEstimate handle_frame(const FeatureFrame& frame);
  /// After a failed solve of `frame` (failure_recovery.cpp): restart from the last good estimate
  /// and solve the frame again, or re-initialize in a new map frame when that is not possible.
  StateEstimate recover(const FeatureFrame& frame, const std::string& why);
  /// Empties the window, its tracks and priors; with `new_map_frame`, also what ties W to the
  /// world (ENU registration, magnetometer reference) and the initialization.
  void clear_window(bool new_map_frame);
  StateEstimate initialize(const FeatureFrame& frame, Timestamp t);
  StateEstimate collect_for_visual_initialization(const FeatureFrame& frame, Timestamp t);
  bool visual_initialization();
  StateEstimate initializing_estimate(Timestamp frame_t) const;
  /// The rest of a frame once its state is in the window: solve, mode, covariance, estimate, then
  /// keep it as a keyframe (sliding the window) or drop it.
  StateEstimate solve_newest(const FeatureFrame& frame, bool keyframe);
  void add_observations(std::uint64_t frame_id, const FeatureFrame& frame);
  bool decide_keyframe(const WindowState& last_keyframe, const WindowState& newest, std::size_t observed) const;
  void initialize_tracks();
  std::optional<double> triangulate(const FeatureTrack& track) const;
  const WindowState* state(std::uint64_t id) const;
  SE3 T_W_C(const WindowState& s) const { return s.T_W_B() * pose_from_block(extrinsic); }
  bool bearing_estimated() const { return cfg.anchor_bearing == AnchorBearing::kEstimated; }
  /// A far track (anchor depth beyond far_threshold) whose inverse depth far_policy=fixed holds.
  bool far_fixed(const FeatureTrack& track) const {
    if (track.handed_over) return false;
    const auto& depth = track.anchor().depth_m;
    const bool near = depth && *depth <= cfg.far_threshold_m && sigma_lambda > 0;
    return depth && !near && cfg.far_policy == FarFeaturePolicy::kFixed;
  }
  /// The track's parameter block: its whole landmark when the anchor bearing is estimated, else
  /// (and for a far-fixed track, which keeps its bearing too) its inverse depth alone.
  double* landmark_block(FeatureTrack& track) const {
    return track.handed_over || (bearing_estimated() && !far_fixed(track)) ? track.landmark : &track.inverse_depth();
  }
  /// A block the marginalization prior holds (a handed-over landmark's is, while its track lives).
  bool in_marginal_prior(const double* block) const {
    return marginal_prior && marginal_prior->index_of(block) >= 0;
  }
  /// Leaving anchors handed over (estimator.features.leaving_anchor = hand_over): the live tracks
  /// anchored at `leaving` whose whole landmark is estimated keep it, anchored at the leaving
  /// pose as it is now; returns their landmark blocks (kept in the prior, not marginalized).
  std::set<const double*> hand_over_tracks_of(const WindowState& leaving);
  /// Marginalizes the tracks' landmark blocks out of the prior before the tracks are erased.
  void drop_from_marginal_prior(const std::vector<std::uint64_t>& track_ids);
  int landmark_block_size() const { return bearing_estimated() ? 3 : 1; }

  /// The window's factors; `constant_blocks` receives the blocks they hold constant (fixed inverse
  /// depths, handed-over tracks' frozen anchors).
  std::vector<Residual> build_residuals(VisualCount* count, std::vector<double*>* constant_blocks);
  /// Solves the window (with `newest_only`, the newest state alone, the rest held); with
  /// `covariance`, also the newest state's covariance from the whole window (nullopt on failure).
  VisualCount solve(std::optional<NewestCovariance>* covariance = nullptr, bool newest_only = false);
  /// The Schur solvers' elimination group (estimator.solver.schur_ordering): the variable landmark
  /// blocks, or null for Ceres' own choice.
  std::shared_ptr<ceres::ParameterBlockOrdering> schur_ordering(const ceres::Problem& problem,
                                                                const std::vector<Residual>& residuals);
  std::optional<NewestCovariance> newest_covariance(ceres::Problem& problem, const std::vector<Residual>& residuals);
  void accumulate_residual_statistics(const std::vector<Residual>& residuals);
  void count_newest_inliers(const std::vector<Residual>& residuals, VisualCount& count) const;
  void remove_failed_tracks();
  StateEstimate estimate_of(const WindowState& s, Timestamp frame_t, EstimatorMode mode, const Mat15& cov) const;
  void slide_out_oldest();
  void reanchor_tracks_of(const WindowState& leaving);
  void trim_imu();
  /// The first state's prior; `extra_sigma_roll_pitch` adds (in quadrature) what the data say
  /// beyond the configured roll-pitch error (a vibrating still start's mean accelerometer).
  Mat15 initial_covariance(const Quat& q, double extra_sigma_roll_pitch = 0.0) const;
};

}  // namespace navaid::estimation
