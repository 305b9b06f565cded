#include "navaid/estimation/sliding_window_estimator.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/gps_position_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/feature_track_store.hpp"
#include "navaid/estimation/gps_registration.hpp"
#include "navaid/estimation/imu_preintegration.hpp"
#include "navaid/estimation/marginalization.hpp"
#include "navaid/estimation/state_prior_factor.hpp"

namespace navaid::estimation {

namespace {

// Re-integrate a preintegration when the bias estimate left its linearization point this far
// (the first-order correction is good well beyond; VINS uses similar values).
constexpr double kRepropagateGyro = 5e-3;   // [rad/s]
constexpr double kRepropagateAccel = 5e-2;  // [m/s^2]
// Feature depths outside this range after a solve are failures (VINS-Mono removes them too).
constexpr double kMinFeatureDepth = 0.05;  // [m]
constexpr double kMaxFeatureDepth = 500.0;
// Triangulation needs this much angle between the extreme rays.
constexpr double kMinTriangulationAngle = 1.0 * M_PI / 180.0;
// Gauge prior of the first state (position and yaw define W) and, with marginalization off, of
// the oldest keyframe that holds the window in place.
constexpr double kGaugeSigma = 1e-3;
constexpr double kPinnedPoseSigma = 1e-4;
constexpr double kLooseSpeedBiasSigma = 1e2;
// Covariance reported before initialization (nothing is known).
constexpr double kUnknownVariance = 1e4;
// Height offset of T_ENU_W when the registration had no fix heights [m].
constexpr double kUnregisteredHeightSigma = 100.0;
// Prior of the magnetic heading of W: only a starting point (the first samples' heading depends
// on the still start's roll and pitch, which the accelerometer bias tilts: a fixed reference
// measured 0.025 rad of yaw error on lab-walk-1), and of its unused translation part.
constexpr double kMagHeadingPriorSigma = 1.0;  // [rad]
constexpr double kMagUnusedPriorSigma = 1.0;

struct WindowState {
  std::uint64_t id = 0;
  Timestamp t = 0;  // IMU clock
  double pose[kPoseSize] = {0, 0, 0, 0, 0, 0, 1};
  double speed_bias[kSpeedBiasSize] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  bool keyframe = false;
  std::optional<ImuPreintegration> imu;  // from the previous state of the window
  std::optional<GpsFix> gps;             // a fix taken at this state's time (within half a frame)
  std::optional<Vec3> mag_B;             // calibrated field at this state's time
  bool mag_decided = false;              // the samples around t have arrived (mag_B set or none usable)

  SE3 T_W_B() const { return pose_from_block(pose); }
  Vec3 v() const { return Vec3(speed_bias[0], speed_bias[1], speed_bias[2]); }
  Vec3 b_g() const { return Vec3(speed_bias[3], speed_bias[4], speed_bias[5]); }
  Vec3 b_a() const { return Vec3(speed_bias[6], speed_bias[7], speed_bias[8]); }
};

struct Residual {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;
  std::vector<double*> blocks;
};

struct NewestCovariance {
  Mat15 state;
  std::optional<Mat4> enu_alignment;  // [yaw, t_x, t_y, t_z] when T_ENU_W is in the window
};

struct VisualCount {
  std::size_t features = 0;        // tracks with factors that the newest frame observes
  std::size_t depth_features = 0;  // ... of which with a depth factor
  std::size_t all_features = 0;    // tracks with factors in the window
};

}  // namespace

struct SlidingWindowEstimator::Impl {
  EstimatorConfig cfg;
  CameraCalibration camera;
  std::shared_ptr<const CameraModel> camera_model;
  ImuNoise imu_noise;
  double focal_px = 0;
  double sigma_lambda = 0;  // 0: no depth noise model (depth factors unusable)
  Timestamp camera_to_imu_ns = 0;
  double extrinsic[kPoseSize];
  std::shared_ptr<ceres::LossFunction> loss;

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
  std::shared_ptr<MarginalizationPrior> mag_prior;

  std::deque<std::unique_ptr<WindowState>> window;  // oldest first; addresses stay put
  FeatureTrackStore tracks;
  std::vector<ImuSample> imu;
  std::deque<FeatureFrame> pending;
  std::shared_ptr<MarginalizationPrior> marginal_prior;
  std::shared_ptr<StatePriorFactor> state_prior;
  std::uint64_t state_prior_id = 0;
  std::uint64_t next_id = 0;
  bool initialized = false;
  Timestamp last_event_t = std::numeric_limits<Timestamp>::min();
  std::optional<Timestamp> imu_only_since;
  std::optional<StateEstimate> last_estimate;
  EstimatorStatistics stats;

  Impl(const RigCalibration& rig, const EstimatorConfig& config, const std::string& camera_name,
       const std::optional<GeodeticOrigin>& geodetic_origin);
  void attach_gps(WindowState& s);
  void register_gps(const WindowState& s);
  void reregister_gps(const WindowState& s);
  GpsRegistration registration(const std::vector<GpsRegistrationPair>& pairs) const;
  void attach_mag(WindowState& s);
  void set_mag_reference(const Vec3& field_B, const SE3& T_W_B);
  double* mag_alignment_block() { return enu_registered ? enu_alignment : mag_alignment; }
  Vec3 fix_enu(const GpsFix& fix) const;
  Impl(const Impl& other);

  std::vector<StateEstimate> process(const SensorEvent& event);
  StateEstimate handle_frame(const FeatureFrame& frame);
  StateEstimate initialize(const FeatureFrame& frame, Timestamp t);
  void add_observations(std::uint64_t frame_id, const FeatureFrame& frame);
  bool decide_keyframe(const WindowState& last_keyframe, const WindowState& newest, std::size_t observed) const;
  void initialize_tracks();
  std::optional<double> triangulate(const FeatureTrack& track) const;
  const WindowState* state(std::uint64_t id) const;
  SE3 T_W_C(const WindowState& s) const { return s.T_W_B() * pose_from_block(extrinsic); }

  std::vector<Residual> build_residuals(VisualCount* count, std::vector<double*>* fixed_inverse_depths);
  /// Solves the window; with `covariance`, also the newest state's covariance (nullopt on failure).
  VisualCount solve(std::optional<NewestCovariance>* covariance = nullptr);
  std::optional<NewestCovariance> newest_covariance(ceres::Problem& problem);
  void remove_failed_tracks();
  StateEstimate estimate_of(const WindowState& s, Timestamp frame_t, EstimatorMode mode, const Mat15& cov) const;
  void slide_out_oldest();
  void reanchor_tracks_of(const WindowState& leaving);
  void trim_imu();
  Mat15 initial_covariance(const Quat& q) const;
};

namespace {

std::shared_ptr<ceres::LossFunction> make_loss(const EstimatorConfig& cfg) {
  switch (cfg.loss) {
    case LossKind::kCauchy: return std::make_shared<ceres::CauchyLoss>(cfg.loss_scale);
    case LossKind::kHuber: return std::make_shared<ceres::HuberLoss>(cfg.loss_scale);
    case LossKind::kNone: return nullptr;
  }
  return nullptr;
}

ceres::LinearSolverType solver_type(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kDenseSchur: return ceres::DENSE_SCHUR;
    case LinearSolverKind::kSparseSchur: return ceres::SPARSE_SCHUR;
    case LinearSolverKind::kSparseNormalCholesky: return ceres::SPARSE_NORMAL_CHOLESKY;
  }
  return ceres::DENSE_SCHUR;
}

/// Covariance of [yaw, t_x, t_y, t_z]; a registration without heights leaves t_z loosely known.
Mat4 alignment_covariance(const GpsRegistration& r) {
  Mat4 P = Mat4::Identity() * kUnregisteredHeightSigma * kUnregisteredHeightSigma;
  const int n = static_cast<int>(r.covariance.rows());
  P.topLeftCorner(n, n) = r.covariance;
  return P;
}

}  // namespace

SlidingWindowEstimator::Impl::Impl(const RigCalibration& rig, const EstimatorConfig& config,
                                   const std::string& camera_name, const std::optional<GeodeticOrigin>& geodetic_origin)
    : cfg(config), origin(geodetic_origin), gps_lever_arm_B(rig.gps_lever_arm_B) {
  if (cfg.use_gps && !origin)
    throw ConfigError("recording", "origin", "GPS factors need the geodetic origin of the ENU frame");
  gps_loss = std::make_shared<ceres::HuberLoss>(cfg.gps_huber_threshold);
  if (rig.cameras.empty()) throw ConfigError("calibration", "cameras", "the estimator needs a camera");
  const CameraCalibration* cam = &rig.cameras.front();
  if (!camera_name.empty()) {
    cam = nullptr;
    for (const auto& c : rig.cameras)
      if (c.name == camera_name) cam = &c;
    if (!cam) throw ConfigError("calibration", "cameras", "no camera named '" + camera_name + "'");
  }
  camera = *cam;
  camera_model = make_camera_model(camera, "calibration");
  if (!rig.imu) throw ConfigError("calibration", "imu", "the estimator needs an IMU calibration");
  imu_noise = ImuNoise::from(*rig.imu);
  validate(imu_noise, "calibration: imu");
  focal_px = std::sqrt(camera.fx * camera.fy);
  camera_to_imu_ns = static_cast<Timestamp>(std::llround(camera.time_offset_s * 1e9));
  pose_to_block(camera.T_B_C, extrinsic);

  const double sigma_d = cfg.disparity_sigma_px > 0 ? cfg.disparity_sigma_px : camera.depth_disparity_sigma_px;
  const double baseline = cfg.depth_baseline_m > 0 ? cfg.depth_baseline_m : camera.depth_baseline_m;
  if (sigma_d > 0 && baseline > 0) sigma_lambda = inverse_depth_sigma(sigma_d, focal_px, baseline);
  if (cfg.use_depth && (cfg.use_inverse_depth || cfg.use_depth_3d) && sigma_lambda <= 0)
    throw ConfigError("calibration", "cameras." + camera.name + ".depth",
                      "depth factors need the depth baseline and disparity sigma (calibration or "
                      "estimator.depth.baseline / estimator.depth.disparity_sigma), or estimator.depth.enabled=false");
  loss = make_loss(cfg);
  if (cfg.use_mag) mag_sigma_yaw = magnetometer_yaw_sigma(cfg.mag_sigma, cfg.mag_reference_field_enu);
}

SlidingWindowEstimator::Impl::Impl(const Impl& o)
    : cfg(o.cfg),
      camera(o.camera),
      camera_model(o.camera_model),
      imu_noise(o.imu_noise),
      focal_px(o.focal_px),
      sigma_lambda(o.sigma_lambda),
      camera_to_imu_ns(o.camera_to_imu_ns),
      loss(o.loss),
      origin(o.origin),
      gps_lever_arm_B(o.gps_lever_arm_B),
      gps_loss(o.gps_loss),
      pending_fixes(o.pending_fixes),
      registration_pairs(o.registration_pairs),
      enu_registered(o.enu_registered),
      enu_prior(o.enu_prior ? std::make_shared<MarginalizationPrior>(*o.enu_prior) : nullptr),
      decoupled_T_ENU_W(o.decoupled_T_ENU_W),
      decoupled_covariance(o.decoupled_covariance),
      mag(o.mag),
      mag_sigma_yaw(o.mag_sigma_yaw),
      mag_referenced(o.mag_referenced),
      mag_prior(o.mag_prior ? std::make_shared<MarginalizationPrior>(*o.mag_prior) : nullptr),
      tracks(o.tracks),
      imu(o.imu),
      pending(o.pending),
      state_prior(o.state_prior),
      state_prior_id(o.state_prior_id),
      next_id(o.next_id),
      initialized(o.initialized),
      last_event_t(o.last_event_t),
      imu_only_since(o.imu_only_since),
      last_estimate(o.last_estimate),
      stats(o.stats) {
  std::copy(o.extrinsic, o.extrinsic + kPoseSize, extrinsic);
  std::copy(o.enu_alignment, o.enu_alignment + kEnuAlignmentSize, enu_alignment);
  std::copy(o.mag_alignment, o.mag_alignment + kEnuAlignmentSize, mag_alignment);
  std::unordered_map<const double*, double*> moved;
  moved[o.enu_alignment] = enu_alignment;
  moved[o.mag_alignment] = mag_alignment;
  for (const auto& s : o.window) {
    window.push_back(std::make_unique<WindowState>(*s));
    moved[s->pose] = window.back()->pose;
    moved[s->speed_bias] = window.back()->speed_bias;
  }
  if (enu_prior) enu_prior->remap(moved);
  if (mag_prior) mag_prior->remap(moved);
  if (o.marginal_prior) {
    marginal_prior = std::make_shared<MarginalizationPrior>(*o.marginal_prior);
    marginal_prior->remap(moved);
  }
}

const WindowState* SlidingWindowEstimator::Impl::state(std::uint64_t id) const {
  for (const auto& s : window)
    if (s->id == id) return s.get();
  return nullptr;
}

std::vector<StateEstimate> SlidingWindowEstimator::Impl::process(const SensorEvent& event) {
  const Timestamp t = event_time(event);
  if (t < last_event_t)
    throw Error("estimator: events out of time order (" + std::to_string(t) + " ns after " +
                std::to_string(last_event_t) + " ns)");
  last_event_t = t;
  std::vector<StateEstimate> out;
  if (const auto* s = std::get_if<ImuSample>(&event)) {
    if (!s->has_gyro) throw Error("estimator: IMU sample without gyro data at " + std::to_string(s->t) + " ns");
    if (!imu.empty() && s->t <= imu.back().t) return out;  // duplicate time stamp: keep the first
    imu.push_back(*s);
    trim_imu();
  } else if (const auto* f = std::get_if<FeatureFrame>(&event)) {
    if (f->camera == camera.name) pending.push_back(*f);
  } else if (std::holds_alternative<RgbdFrame>(event)) {
    throw Error("image front end not available yet: run on a feature-level recording");
  }
  if (const auto* g = std::get_if<GpsFix>(&event)) {
    if (cfg.use_gps && g->mode != GpsFixMode::kNoFix && ellipsoidal_height_m(*g)) pending_fixes.push_back(*g);
  }
  if (const auto* m = std::get_if<MagSample>(&event)) {
    if (cfg.use_mag && m->field.allFinite() && (mag.empty() || m->t > mag.back().t))
      mag.push_back({m->t, calibrated_mag_field(cfg, m->field)});
  }
  while (!pending.empty() && !imu.empty() && pending.front().t + camera_to_imu_ns <= imu.back().t) {
    out.push_back(handle_frame(pending.front()));
    pending.pop_front();
  }
  return out;
}

void SlidingWindowEstimator::Impl::trim_imu() {
  if (window.empty() || imu.size() < 4096) return;
  const Timestamp keep_from = window.front()->t;
  std::size_t first = 0;
  while (first + 1 < imu.size() && imu[first + 1].t <= keep_from) ++first;
  if (first > 2048) imu.erase(imu.begin(), imu.begin() + static_cast<std::ptrdiff_t>(first));
}

Mat15 SlidingWindowEstimator::Impl::initial_covariance(const Quat& q) const {
  Mat15 P = Mat15::Zero();
  // Roll and pitch come from gravity; yaw and position define W (world-frame angles, converted
  // to the right perturbation of StateEstimate).
  const Vec3 sigma_world(cfg.init_sigma_roll_pitch_rad, cfg.init_sigma_roll_pitch_rad, kGaugeSigma);
  const Mat3 R = q.toRotationMatrix();
  P.block<3, 3>(0, 0) = R.transpose() * sigma_world.cwiseAbs2().asDiagonal() * R;
  P.block<3, 3>(3, 3) = Mat3::Identity() * kGaugeSigma * kGaugeSigma;
  P.block<3, 3>(6, 6) = Mat3::Identity() * cfg.init_sigma_velocity * cfg.init_sigma_velocity;
  P.block<3, 3>(9, 9) = Mat3::Identity() * cfg.init_sigma_gyro_bias * cfg.init_sigma_gyro_bias;
  P.block<3, 3>(12, 12) = Mat3::Identity() * cfg.init_sigma_accel_bias * cfg.init_sigma_accel_bias;
  return P;
}

StateEstimate SlidingWindowEstimator::Impl::estimate_of(const WindowState& s, Timestamp frame_t, EstimatorMode mode,
                                                        const Mat15& cov) const {
  StateEstimate e;
  e.t = frame_t;
  e.T_W_B = s.T_W_B();
  e.v_W = s.v();
  e.b_g = s.b_g();
  e.b_a = s.b_a();
  e.covariance = cov;
  e.mode = mode;
  return e;
}

StateEstimate SlidingWindowEstimator::Impl::initialize(const FeatureFrame& frame, Timestamp t) {
  const Timestamp still_ns = static_cast<Timestamp>(std::llround(cfg.still_duration_s * 1e9));
  const std::vector<ImuSample> samples = imu_samples_between(imu, t - still_ns, t);
  Vec3 accel = Vec3::Zero();
  for (const auto& s : samples) accel += s.accel;
  accel /= static_cast<double>(samples.size());
  if (!(accel.norm() > 1.0))
    throw Error("estimator: the mean specific force of the still start is " + std::to_string(accel.norm()) +
                " m/s^2; cannot find gravity");
  // At rest the accelerometer measures -g: R_W_B accel points up. Yaw is unobservable: 0.
  const Quat q_up = Quat::FromTwoVectors(accel, Vec3::UnitZ());
  const Vec3 rpy = rpy_from_quat(q_up);
  const Quat q = quat_from_rpy(rpy.x(), rpy.y(), 0.0);

  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  s->keyframe = true;
  pose_to_block(SE3(q, Vec3::Zero()), s->pose);
  const Mat15 P0 = initial_covariance(q);
  state_prior = std::make_shared<StatePriorFactor>(s->T_W_B(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), P0);
  state_prior_id = s->id;
  if (cfg.use_mag) {
    // Standing still, the mean field of the still start is the best first guess of psi.
    Vec3 field = Vec3::Zero();
    int n = 0;
    for (const auto& m : mag)
      if (m.t >= t - still_ns && m.t <= t) field += m.field, ++n;
    if (n > 0 && field.norm() > 0) set_mag_reference(field / n, s->T_W_B());
  }
  window.push_back(std::move(s));
  add_observations(window.back()->id, frame);
  initialize_tracks();
  initialized = true;
  ++stats.keyframes;
  return estimate_of(*window.back(), frame.t, EstimatorMode::kInitializing, P0);
}

void SlidingWindowEstimator::Impl::add_observations(std::uint64_t frame_id, const FeatureFrame& frame) {
  std::vector<std::pair<std::uint64_t, TrackObservation>> obs;
  obs.reserve(frame.features.size());
  for (const auto& f : frame.features) {
    const auto m = camera_model->undistort(camera_model->distorted_from_pixel(f.uv));
    if (!m) continue;
    TrackObservation o;
    o.m = *m;
    o.uv = f.uv;
    if (cfg.use_depth && f.depth_m && std::isfinite(*f.depth_m) && *f.depth_m > 0) o.depth_m = f.depth_m;
    obs.emplace_back(f.track_id, o);
  }
  tracks.add_frame(frame_id, obs);
}

bool SlidingWindowEstimator::Impl::decide_keyframe(const WindowState& last_keyframe, const WindowState& newest,
                                                   std::size_t observed) const {
  int common = 0;
  const double parallax = tracks.mean_parallax_px(last_keyframe.id, newest.id, &common);
  if (common > 0 && parallax >= cfg.keyframe_parallax_px) return true;
  // Track loss: few tracks shared with the last keyframe while new ones appeared (they need an
  // anchor in the window). A frame that sees next to nothing gains nothing from being a keyframe.
  if (common < cfg.keyframe_min_tracked && observed > static_cast<std::size_t>(common)) return true;
  return ns_to_seconds(newest.t - last_keyframe.t) >= cfg.keyframe_max_interval_s;
}

std::optional<double> SlidingWindowEstimator::Impl::triangulate(const FeatureTrack& track) const {
  const WindowState* anchor = state(track.anchor().frame_id);
  if (!anchor) return std::nullopt;
  const SE3 T_W_Ca = T_W_C(*anchor);
  // Linear triangulation in the anchor camera: m_j x (R_ja P + t_ja) = 0 for every observation.
  Mat3 A = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  double max_angle = 0;
  const Vec3 ray_a = T_W_Ca.q * Vec3(track.anchor().m.x(), track.anchor().m.y(), 1.0).normalized();
  for (const auto& o : track.observations) {
    const WindowState* s = state(o.frame_id);
    if (!s) return std::nullopt;
    const SE3 T_j_a = T_W_C(*s).inverse() * T_W_Ca;
    const Vec3 m(o.m.x(), o.m.y(), 1.0);
    const Mat3 M = hat(m);
    const Eigen::Matrix3d MR = M * T_j_a.rotation();
    A += MR.transpose() * MR;
    b -= MR.transpose() * (M * T_j_a.t);
    const Vec3 ray = T_W_C(*s).q * m.normalized();
    max_angle = std::max(max_angle, std::acos(std::clamp(ray.dot(ray_a), -1.0, 1.0)));
  }
  if (max_angle < kMinTriangulationAngle) return std::nullopt;
  const Eigen::LDLT<Mat3> ldlt(A);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Vec3 P = ldlt.solve(b);
  if (!P.allFinite() || P.z() < kMinFeatureDepth || P.z() > kMaxFeatureDepth) return std::nullopt;
  return 1.0 / P.z();
}

void SlidingWindowEstimator::Impl::initialize_tracks() {
  for (auto& [id, track] : tracks.tracks()) {
    if (track.initialized) continue;
    if (track.anchor().depth_m) {
      track.inverse_depth = 1.0 / *track.anchor().depth_m;
      track.initialized = true;
    } else if (track.observations.size() >= 2) {
      if (const auto lambda = triangulate(track)) {
        track.inverse_depth = *lambda;
        track.initialized = true;
      }
    }
  }
}

std::vector<Residual> SlidingWindowEstimator::Impl::build_residuals(VisualCount* count,
                                                                    std::vector<double*>* fixed_inverse_depths) {
  std::vector<Residual> out;
  // IMU between consecutive states, re-integrated when the bias moved far from its linearization.
  for (std::size_t i = 1; i < window.size() && cfg.use_imu; ++i) {
    WindowState& prev = *window[i - 1];
    WindowState& cur = *window[i];
    cur.imu->repropagate_if_needed(prev.b_g(), prev.b_a(), kRepropagateGyro, kRepropagateAccel);
    out.push_back({std::make_shared<ImuFactor>(*cur.imu), nullptr, {prev.pose, prev.speed_bias, cur.pose, cur.speed_bias}});
  }
  if (marginal_prior && !marginal_prior->empty())
    out.push_back({std::make_shared<MarginalizationFactor>(marginal_prior), nullptr, marginal_prior->blocks});
  if (state_prior) {
    for (auto& s : window)
      if (s->id == state_prior_id) out.push_back({state_prior, nullptr, {s->pose, s->speed_bias}});
  }

  if (enu_prior) out.push_back({std::make_shared<MarginalizationFactor>(enu_prior), nullptr, enu_prior->blocks});
  if (mag_prior) out.push_back({std::make_shared<MarginalizationFactor>(mag_prior), nullptr, mag_prior->blocks});
  if (enu_registered) {
    for (auto& s : window)
      if (s->gps)
        out.push_back({std::make_shared<GpsPositionFactor>(fix_enu(*s->gps), s->gps->covariance_enu, gps_lever_arm_B),
                       gps_loss, {s->pose, enu_alignment}});
  }

  for (auto& s : window) {
    // A field without a horizontal part at the current attitude has no heading (the factor could
    // not be evaluated): leave it out of this solve.
    if (!s->mag_B) continue;
    const Vec3 h = s->T_W_B().q * *s->mag_B;
    if (h.head<2>().norm() < 1e-3 * h.norm()) continue;
    out.push_back({std::make_shared<MagnetometerYawFactor>(*s->mag_B, cfg.mag_reference_field_enu, mag_sigma_yaw),
                   nullptr, {s->pose, mag_alignment_block()}});
  }

  const std::uint64_t newest_id = window.back()->id;
  VisualCount c;
  for (auto& [id, track] : tracks.tracks()) {
    if (!track.initialized || track.observations.size() < 2) continue;
    const TrackObservation& a = track.anchor();
    WindowState* anchor = nullptr;
    for (auto& s : window)
      if (s->id == a.frame_id) anchor = s.get();
    if (!anchor) continue;
    const SE3 T_W_Ca = T_W_C(*anchor);
    const bool near = a.depth_m && *a.depth_m <= cfg.far_threshold_m && sigma_lambda > 0;
    const bool fixed = a.depth_m && !near && cfg.far_policy == FarFeaturePolicy::kFixed;
    std::vector<Residual> r;
    bool depth_factor = false;
    bool sees_newest = false;
    for (std::size_t k = 1; k < track.observations.size(); ++k) {
      const TrackObservation& o = track.observations[k];
      WindowState* target = nullptr;
      for (auto& s : window)
        if (s->id == o.frame_id) target = s.get();
      if (!target) continue;
      // A point behind the target camera at the current estimate cannot be evaluated (the factor
      // returns false and Ceres aborts): leave that observation out of this solve.
      const Vec3 p_ct = T_W_C(*target).inverse() * (T_W_Ca * (Vec3(a.m.x(), a.m.y(), 1.0) / track.inverse_depth));
      if (!(p_ct.z() > kMinFeatureDepth)) continue;
      sees_newest |= o.frame_id == newest_id;
      std::vector<double*> blocks{anchor->pose, target->pose, extrinsic, &track.inverse_depth};
      if (near && cfg.use_depth_3d && o.depth_m && *o.depth_m <= cfg.far_threshold_m) {
        r.push_back({std::make_shared<Depth3dFactor>(a.m, o.m, *o.depth_m, focal_px, sigma_lambda, cfg.pixel_sigma_px),
                     loss, blocks});
        depth_factor = true;
      } else if (cfg.use_reprojection) {
        r.push_back({std::make_shared<ReprojectionFactor>(a.m, o.m, focal_px, cfg.pixel_sigma_px), loss, blocks});
      }
    }
    if (r.empty()) continue;
    if (near && cfg.use_inverse_depth) {
      r.push_back({std::make_shared<InverseDepthFactor>(*a.depth_m, sigma_lambda), nullptr, {&track.inverse_depth}});
      depth_factor = true;
    }
    if (fixed && fixed_inverse_depths) fixed_inverse_depths->push_back(&track.inverse_depth);
    ++c.all_features;
    if (sees_newest || a.frame_id == newest_id) {
      ++c.features;
      if (depth_factor) ++c.depth_features;
    }
    for (auto& x : r) out.push_back(std::move(x));
  }
  if (count) *count = c;
  return out;
}

VisualCount SlidingWindowEstimator::Impl::solve(std::optional<NewestCovariance>* covariance) {
  ceres::Problem::Options po;
  // The problem borrows the factors, losses and manifold; they live in this scope.
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const std::unique_ptr<ceres::Manifold> manifold = make_pose_manifold();
  VisualCount count;
  std::vector<double*> fixed;
  const std::vector<Residual> residuals = build_residuals(&count, &fixed);
  for (auto& s : window) {
    problem.AddParameterBlock(s->pose, kPoseSize, manifold.get());
    problem.AddParameterBlock(s->speed_bias, kSpeedBiasSize);
    if (!cfg.use_imu) problem.SetParameterBlockConstant(s->speed_bias);
  }
  problem.AddParameterBlock(extrinsic, kPoseSize, manifold.get());
  problem.SetParameterBlockConstant(extrinsic);
  for (const auto& r : residuals) problem.AddResidualBlock(r.cost.get(), r.loss.get(), r.blocks);
  for (double* lambda : fixed) problem.SetParameterBlockConstant(lambda);
  if (!cfg.use_imu && !state_prior && (!marginal_prior || marginal_prior->empty()))
    problem.SetParameterBlockConstant(window.front()->pose);  // without IMU nothing else holds the gauge

  ceres::Solver::Options so;
  so.linear_solver_type = solver_type(cfg.linear_solver);
  so.max_num_iterations = cfg.max_iterations;
  if (cfg.max_solver_time_s > 0) so.max_solver_time_in_seconds = cfg.max_solver_time_s;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  ++stats.solves;
  stats.features_in_last_solve = count.all_features;
  stats.depth_features_in_last_solve = count.depth_features;
  if (covariance) *covariance = newest_covariance(problem);
  return count;
}

std::optional<NewestCovariance> SlidingWindowEstimator::Impl::newest_covariance(ceres::Problem& problem) {
  const WindowState& s = *window.back();
  const bool with_enu = problem.HasParameterBlock(enu_alignment);
  NewestCovariance out;
  Eigen::Matrix<double, 15, 15> C;  // Ceres tangent [dp, d, v, b_g, b_a]
  if (cfg.covariance_method == CovarianceMethod::kCeres) {
    if (problem.IsParameterBlockConstant(s.speed_bias)) return std::nullopt;
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::SPARSE_QR;
    co.num_threads = 1;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs = {
        {s.pose, s.pose}, {s.pose, s.speed_bias}, {s.speed_bias, s.speed_bias}};
    if (with_enu) pairs.emplace_back(enu_alignment, enu_alignment);
    if (!covariance.Compute(pairs, &problem)) return std::nullopt;
    Eigen::Matrix<double, 15, 15, Eigen::RowMajor> Cr;
    if (!covariance.GetCovarianceMatrixInTangentSpace({s.pose, s.speed_bias}, Cr.data())) return std::nullopt;
    C = Cr;
    if (with_enu) {
      Eigen::Matrix<double, 4, 4, Eigen::RowMajor> A;
      if (!covariance.GetCovarianceBlock(enu_alignment, enu_alignment, A.data())) return std::nullopt;
      out.enu_alignment = A;
    }
  } else {
    // Same quantity from the Gauss-Newton information J^T J (robust losses applied, as
    // ceres::Covariance does): Schur-complement the inverse depths (a diagonal block), then the
    // newest state's block of the inverse. Columns: T_ENU_W when present, the magnetometer's psi
    // when present, the states oldest first (the newest last), then every free inverse depth;
    // blocks left out of the list are held constant by Evaluate.
    ceres::Problem::EvaluateOptions eo;
    int state_cols = 0;
    if (with_enu) {
      eo.parameter_blocks.push_back(enu_alignment);
      state_cols += kEnuAlignmentSize;
    }
    // psi is correlated with every heading: a column of its own, not held constant.
    if (problem.HasParameterBlock(mag_alignment)) {
      eo.parameter_blocks.push_back(mag_alignment);
      state_cols += kEnuAlignmentSize;
    }
    for (const auto& w : window) {
      eo.parameter_blocks.push_back(w->pose);
      state_cols += kPoseTangentSize;
      if (!problem.IsParameterBlockConstant(w->speed_bias)) {
        eo.parameter_blocks.push_back(w->speed_bias);
        state_cols += kSpeedBiasSize;
      }
    }
    std::vector<double*> all;
    problem.GetParameterBlocks(&all);
    std::set<const double*> states{enu_alignment, mag_alignment};
    for (const auto& w : window) states.insert(w->pose), states.insert(w->speed_bias);
    for (double* b : all)
      if (!states.count(b) && problem.ParameterBlockSize(b) == 1 && !problem.IsParameterBlockConstant(b))
        eo.parameter_blocks.push_back(b);
    ceres::CRSMatrix crs;
    if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs)) return std::nullopt;
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor, int>> J(
        crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()), crs.rows.data(), crs.cols.data(),
        crs.values.data());
    const Eigen::MatrixXd H = Eigen::MatrixXd(Eigen::SparseMatrix<double>(J.transpose() * J));
    const int nl = crs.num_cols - state_cols;
    Eigen::MatrixXd S = H.topLeftCorner(state_cols, state_cols);
    if (nl > 0) {
      Eigen::VectorXd inv_l(nl);
      for (int k = 0; k < nl; ++k) {
        const double h = H(state_cols + k, state_cols + k);
        inv_l(k) = h > 1e-12 ? 1.0 / h : 0.0;  // an unobserved depth carries no information
      }
      const Eigen::MatrixXd H_sl = H.topRightCorner(state_cols, nl);
      S.noalias() -= H_sl * inv_l.asDiagonal() * H_sl.transpose();
    }
    const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
    if (llt.info() != Eigen::Success) return std::nullopt;
    // The newest state's columns are the last ones: its pose, and its speed-bias unless constant.
    const int newest = problem.IsParameterBlockConstant(s.speed_bias) ? kPoseTangentSize : 15;
    const int enu = with_enu ? kEnuAlignmentSize : 0;
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(state_cols, newest + enu);
    E.bottomLeftCorner(newest, newest).setIdentity();
    if (enu) E.topRightCorner(enu, enu).setIdentity();
    const Eigen::MatrixXd X = llt.solve(E);
    C.setZero();
    C.topLeftCorner(newest, newest) = X.bottomLeftCorner(newest, newest);
    // A constant speed-bias (IMU factors off) is not estimated: report it as unknown.
    if (newest < 15) C.bottomRightCorner<9, 9>() = Eigen::Matrix<double, 9, 9>::Identity() * kUnknownVariance;
    if (enu) out.enu_alignment = Mat4(X.topRightCorner(enu, enu));
  }
  // Ceres' tangent [dp, d, v, b_g, b_a], q (+) d = Exp(2 d) q, to StateEstimate's
  // [dtheta_right, dp, dv, db_g, db_a]: dtheta_right = 2 R^T d.
  Mat15 T = Mat15::Zero();
  T.block<3, 3>(0, 3) = 2.0 * s.T_W_B().rotation().transpose();
  T.block<3, 3>(3, 0).setIdentity();
  T.block<9, 9>(6, 6).setIdentity();
  Mat15 P = T * C * T.transpose();
  out.state = 0.5 * (P + P.transpose());
  if (!out.state.allFinite() || (out.enu_alignment && !out.enu_alignment->allFinite())) return std::nullopt;
  return out;
}

Vec3 SlidingWindowEstimator::Impl::fix_enu(const GpsFix& fix) const {
  // The registration's eq. 6 conversion, so that factors and registration agree.
  return geodesic_enu({fix}, *origin).front();
}

void SlidingWindowEstimator::Impl::attach_gps(WindowState& s) {
  const Timestamp tolerance = static_cast<Timestamp>(std::llround(cfg.gps_max_time_offset_s * 1e9));
  while (!pending_fixes.empty() && pending_fixes.front().t < s.t - tolerance) pending_fixes.pop_front();  // missed
  if (!pending_fixes.empty() && pending_fixes.front().t <= s.t + tolerance) {
    s.gps = pending_fixes.front();
    pending_fixes.pop_front();
  }
}

void SlidingWindowEstimator::Impl::register_gps(const WindowState& s) {
  if (enu_registered || !s.gps) return;
  const SE3 T = s.T_W_B();
  registration_pairs.push_back({*s.gps, T * gps_lever_arm_B});
  const GpsRegistration r = registration(registration_pairs);
  if (!r.registered()) return;
  for (int i = 0; i < kEnuAlignmentSize; ++i) enu_alignment[i] = r.alignment(i);
  enu_registered = true;
  // The fixes used here are not factors in the window: their information enters as a Gaussian
  // prior on T_ENU_W (in the marginalization prior's square-root form, J = L^-1, r = 0).
  const Mat4 P = alignment_covariance(r);
  const Eigen::LLT<Mat4> llt(0.5 * (P + P.transpose()));
  if (llt.info() != Eigen::Success) return;
  auto prior = std::make_shared<MarginalizationPrior>();
  prior->blocks = {enu_alignment};
  prior->kinds = {BlockKind::kEuclidean};
  prior->ambient_sizes = {kEnuAlignmentSize};
  prior->tangent_offsets = {0};
  prior->x0 = {std::vector<double>(enu_alignment, enu_alignment + kEnuAlignmentSize)};
  prior->J = llt.matrixL().solve(Mat4::Identity());
  prior->r = Eigen::Vector4d::Zero();
  enu_prior = prior;
  ++stats.gps_registrations;
}

GpsRegistration SlidingWindowEstimator::Impl::registration(const std::vector<GpsRegistrationPair>& pairs) const {
  GpsRegistrationOptions options;
  options.error_correlation_time_s = cfg.gps_correlation_time_s;  // multipath: not independent fixes
  return register_gps_to_world(pairs, *origin, options);
}

void SlidingWindowEstimator::Impl::reregister_gps(const WindowState& s) {
  if (!s.gps) return;
  registration_pairs.push_back({*s.gps, s.T_W_B() * gps_lever_arm_B});
  const std::size_t keep = static_cast<std::size_t>(cfg.gps_registration_fixes);
  if (keep > 0 && registration_pairs.size() > keep)
    registration_pairs.erase(registration_pairs.begin(),
                             registration_pairs.end() - static_cast<std::ptrdiff_t>(keep));
  const GpsRegistration r = registration(registration_pairs);
  // A failed re-registration (too few or too uncertain fixes) keeps the last good alignment.
  if (!r.registered()) return;
  decoupled_T_ENU_W = r.T_ENU_W();
  decoupled_covariance = alignment_covariance(r);
  ++stats.gps_registrations;
}

void SlidingWindowEstimator::Impl::set_mag_reference(const Vec3& field_B, const SE3& T_W_B) {
  const Vec3 h = T_W_B.q * field_B;
  const Vec3& ref = cfg.mag_reference_field_enu;
  // Rz(psi) turns the field's heading in W into the reference heading in ENU.
  mag_alignment[0] = std::remainder(std::atan2(ref.y(), ref.x()) - std::atan2(h.y(), h.x()), 2.0 * M_PI);
  mag_referenced = true;
  auto prior = std::make_shared<MarginalizationPrior>();
  prior->blocks = {mag_alignment};
  prior->kinds = {BlockKind::kEuclidean};
  prior->ambient_sizes = {kEnuAlignmentSize};
  prior->tangent_offsets = {0};
  prior->x0 = {std::vector<double>(mag_alignment, mag_alignment + kEnuAlignmentSize)};
  prior->J = Eigen::Vector4d(1.0 / kMagHeadingPriorSigma, 1.0 / kMagUnusedPriorSigma, 1.0 / kMagUnusedPriorSigma,
                             1.0 / kMagUnusedPriorSigma)
                 .asDiagonal();
  prior->r = Eigen::Vector4d::Zero();
  mag_prior = prior;
}

void SlidingWindowEstimator::Impl::attach_mag(WindowState& s) {
  if (s.mag_decided) return;
  const Timestamp tolerance = static_cast<Timestamp>(std::llround(cfg.mag_max_time_offset_s * 1e9));
  // Decide once every sample that could be used has arrived (deterministic, whatever the rates).
  if (mag.empty() || mag.back().t <= s.t + tolerance) return;
  s.mag_decided = true;
  const auto after = std::lower_bound(mag.begin(), mag.end(), s.t,
                                      [](const MagSample& m, Timestamp t) { return m.t < t; });
  const MagSample* a = after != mag.begin() && s.t - std::prev(after)->t <= tolerance ? &*std::prev(after) : nullptr;
  const MagSample* b = after != mag.end() && after->t - s.t <= tolerance ? &*after : nullptr;
  Vec3 field;
  if (a && b && b->t > a->t) {
    // The field in B follows the head's rotation: interpolate rather than take the nearest.
    const double u = static_cast<double>(s.t - a->t) / static_cast<double>(b->t - a->t);
    field = (1.0 - u) * a->field + u * b->field;
  } else if (a || b) {
    field = (a && (!b || s.t - a->t <= b->t - s.t)) ? a->field : b->field;
  } else {
    return;
  }
  if (!(field.norm() > 0)) return;
  if (!mag_referenced) set_mag_reference(field, s.T_W_B());  // no sample during the still start
  s.mag_B = field;
}

void SlidingWindowEstimator::Impl::remove_failed_tracks() {
  std::vector<std::uint64_t> failed;
  for (const auto& [id, track] : tracks.tracks()) {
    if (!track.initialized) continue;
    const double z = 1.0 / track.inverse_depth;
    if (!std::isfinite(z) || z < kMinFeatureDepth || z > kMaxFeatureDepth) failed.push_back(id);
  }
  for (auto id : failed) tracks.erase(id);
}

void SlidingWindowEstimator::Impl::reanchor_tracks_of(const WindowState& leaving) {
  const SE3 T_W_Cold = T_W_C(leaving);
  for (auto id : tracks.anchored_at(leaving.id)) {
    FeatureTrack& track = tracks.tracks().at(id);
    if (track.observations.size() < 2) continue;  // disappears with the frame
    const WindowState* next = state(track.observations[1].frame_id);
    if (track.initialized && next) {
      const Vec3 m(track.anchor().m.x(), track.anchor().m.y(), 1.0);
      const Vec3 p_new = T_W_C(*next).inverse() * (T_W_Cold * (m / track.inverse_depth));
      track.initialized = p_new.z() > kMinFeatureDepth && p_new.z() < kMaxFeatureDepth;
      if (track.initialized) track.inverse_depth = 1.0 / p_new.z();
    } else {
      track.initialized = false;
    }
  }
}

void SlidingWindowEstimator::Impl::slide_out_oldest() {
  WindowState& oldest = *window.front();
  bool marginalized = false;
  if (cfg.marginalization) {
    // Blocks leaving: the oldest pose and speed-bias, the inverse depths anchored there.
    std::set<const double*> leaving{oldest.pose, oldest.speed_bias};
    for (auto id : tracks.anchored_at(oldest.id)) leaving.insert(&tracks.tracks().at(id).inverse_depth);
    std::vector<double*> fixed;
    const std::vector<Residual> residuals = build_residuals(nullptr, &fixed);
    Marginalizer marg;
    for (auto& s : window) marg.set_manifold(s->pose, BlockKind::kPose);
    marg.set_manifold(extrinsic, BlockKind::kPose);
    marg.set_constant(extrinsic);
    for (double* lambda : fixed) {
      marg.set_constant(lambda);
      leaving.erase(lambda);
    }
    if (!cfg.use_imu)
      for (auto& s : window) marg.set_constant(s->speed_bias);
    if (!cfg.use_imu) leaving.erase(oldest.speed_bias);
    for (const auto& r : residuals) {
      MarginalizationTerm term;
      for (std::size_t i = 0; i < r.blocks.size(); ++i)
        if (leaving.count(r.blocks[i])) term.marginalize.push_back(static_cast<int>(i));
      if (term.marginalize.empty()) continue;
      term.cost = r.cost;
      term.loss = r.loss;
      term.blocks = r.blocks;
      marg.add(std::move(term));
    }
    try {
      marginal_prior = std::make_shared<MarginalizationPrior>(marg.marginalize());
      ++stats.marginalizations;
      marginalized = true;
    } catch (const Error&) {
      // A factor that cannot be linearized here: lose the prior rather than the run, and hold the
      // gauge as without marginalization (below).
      marginal_prior.reset();
      ++stats.marginalization_failures;
    }
    if (state_prior_id == oldest.id) state_prior.reset();  // consumed by the new prior
  }
  if (marginalized && !cfg.reuse_marginalized_tracks) {
    // Ablation: every observation of these tracks is now in the prior; restart them at their
    // next observation instead of re-anchoring (which uses those observations again).
    for (auto id : tracks.anchored_at(oldest.id)) tracks.erase(id);
  } else {
    reanchor_tracks_of(oldest);
  }
  tracks.remove_frame(oldest.id);
  window.pop_front();
  window.front()->imu.reset();
  if (!marginalized) {
    // Hold the gauge: pin the new oldest keyframe where the window put it.
    const WindowState& s = *window.front();
    Mat15 P = Mat15::Identity() * kLooseSpeedBiasSigma * kLooseSpeedBiasSigma;
    P.topLeftCorner<6, 6>() = Mat6::Identity() * kPinnedPoseSigma * kPinnedPoseSigma;
    state_prior = std::make_shared<StatePriorFactor>(s.T_W_B(), s.v(), s.b_g(), s.b_a(), P);
    state_prior_id = s.id;
  }
}

StateEstimate SlidingWindowEstimator::Impl::handle_frame(const FeatureFrame& frame) {
  ++stats.frames;
  const Timestamp t = frame.t + camera_to_imu_ns;
  const Timestamp still_ns = static_cast<Timestamp>(std::llround(cfg.still_duration_s * 1e9));
  if (!initialized) {
    if (imu.empty() || imu.front().t > t - still_ns) {
      StateEstimate e;
      e.t = frame.t;
      e.covariance = Mat15::Identity() * kUnknownVariance;
      e.mode = EstimatorMode::kInitializing;
      return e;
    }
    last_estimate = initialize(frame, t);
    return *last_estimate;
  }
  if (t <= window.back()->t) throw Error("estimator: feature frames must have increasing time stamps");

  const WindowState& last_kf = *window.back();
  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  s->imu = ImuPreintegration::between(imu, last_kf.t, t, imu_noise, last_kf.b_g(), last_kf.b_a());
  SE3 T;
  Vec3 v;
  s->imu->predict(last_kf.T_W_B(), last_kf.v(), last_kf.b_g(), last_kf.b_a(), &T, &v);
  pose_to_block(T, s->pose);
  s->speed_bias[0] = v.x(), s->speed_bias[1] = v.y(), s->speed_bias[2] = v.z();
  for (int i = 3; i < kSpeedBiasSize; ++i) s->speed_bias[i] = last_kf.speed_bias[i];
  window.push_back(std::move(s));
  WindowState& newest = *window.back();
  add_observations(newest.id, frame);
  if (cfg.use_gps) attach_gps(newest);
  if (cfg.use_mag)
    for (auto& w : window) attach_mag(*w);
  // A frame carrying a fix stays in the window, so that its GPS factor does.
  const bool keyframe = decide_keyframe(*window[window.size() - 2], newest, frame.features.size()) ||
                        (newest.gps && enu_registered);
  initialize_tracks();

  std::optional<NewestCovariance> c;
  const VisualCount count = solve(cfg.covariance_method != CovarianceMethod::kOff ? &c : nullptr);
  remove_failed_tracks();
  if (cfg.use_gps && cfg.gps_mode == GpsMode::kJoint) register_gps(newest);
  if (cfg.use_gps && cfg.gps_mode == GpsMode::kDecoupled) reregister_gps(newest);

  EstimatorMode mode;
  if (count.features < static_cast<std::size_t>(cfg.min_visual_features)) {
    if (!imu_only_since) imu_only_since = t;
    mode = ns_to_seconds(t - *imu_only_since) > cfg.lost_after_s ? EstimatorMode::kLost : EstimatorMode::kImuOnly;
  } else {
    imu_only_since.reset();
    mode = count.depth_features > 0 ? EstimatorMode::kRgbdVio : EstimatorMode::kVio;
  }
  if (!T_W_C(newest).t.allFinite() || !newest.T_W_B().q.coeffs().allFinite()) mode = EstimatorMode::kLost;

  Mat15 cov;
  if (c) {
    cov = c->state;
  } else {
    if (cfg.covariance_method != CovarianceMethod::kOff) ++stats.covariance_failures;
    // No covariance from this window: the last one, inflated (never pretend to more certainty),
    // up to the "unknown" level.
    cov = last_estimate ? Mat15(last_estimate->covariance * 1.5) : Mat15(Mat15::Identity() * kUnknownVariance);
    const double largest = cov.diagonal().maxCoeff();
    if (largest > kUnknownVariance) cov *= kUnknownVariance / largest;
  }
  StateEstimate e = estimate_of(newest, frame.t, mode, cov);
  if (enu_registered) {
    e.T_ENU_W = enu_alignment_from_block(enu_alignment);
    if (c && c->enu_alignment) {
      e.T_ENU_W_covariance = *c->enu_alignment;
    } else if (enu_prior) {  // registered after this frame's solve: the registration's covariance
      e.T_ENU_W_covariance = Mat4(enu_prior->information().inverse());
    }
  } else if (decoupled_T_ENU_W) {
    e.T_ENU_W = *decoupled_T_ENU_W;
    e.T_ENU_W_covariance = decoupled_covariance;
  }
  last_estimate = e;

  if (keyframe) {
    newest.keyframe = true;
    ++stats.keyframes;
    if (static_cast<int>(window.size()) > cfg.window_size) slide_out_oldest();
  } else {
    tracks.remove_frame(newest.id);
    window.pop_back();
  }
  const Timestamp mag_keep_from = window.front()->t - seconds_to_ns(1.0);
  while (!mag.empty() && mag.front().t < mag_keep_from) mag.pop_front();
  return e;
}

// ---------------------------------------------------------------------------------------------

SlidingWindowEstimator::SlidingWindowEstimator(const RigCalibration& rig, const EstimatorConfig& config,
                                               const std::string& camera_name,
                                               const std::optional<GeodeticOrigin>& origin)
    : impl_(std::make_unique<Impl>(rig, config, camera_name, origin)) {}
SlidingWindowEstimator::~SlidingWindowEstimator() = default;
SlidingWindowEstimator::SlidingWindowEstimator(const SlidingWindowEstimator& other)
    : impl_(std::make_unique<Impl>(*other.impl_)) {}
SlidingWindowEstimator::SlidingWindowEstimator(SlidingWindowEstimator&&) noexcept = default;
SlidingWindowEstimator& SlidingWindowEstimator::operator=(SlidingWindowEstimator&&) noexcept = default;

std::vector<StateEstimate> SlidingWindowEstimator::process(const SensorEvent& event) { return impl_->process(event); }

std::vector<StateEstimate> SlidingWindowEstimator::finish() {
  std::vector<StateEstimate> out;
  for (const auto& f : impl_->pending) {
    ++impl_->stats.frames;
    StateEstimate e;
    if (impl_->last_estimate) e = *impl_->last_estimate;
    else e.covariance = Mat15::Identity() * kUnknownVariance;
    e.t = f.t;
    e.mode = EstimatorMode::kLost;
    out.push_back(e);
  }
  impl_->pending.clear();
  return out;
}

std::size_t SlidingWindowEstimator::optimize() {
  if (impl_->window.empty()) return 0;
  return impl_->solve().all_features;
}

const EstimatorConfig& SlidingWindowEstimator::config() const { return impl_->cfg; }
const EstimatorStatistics& SlidingWindowEstimator::statistics() const { return impl_->stats; }
std::size_t SlidingWindowEstimator::window_keyframes() const {
  std::size_t n = 0;
  for (const auto& s : impl_->window) n += s->keyframe ? 1 : 0;
  return n;
}

}  // namespace navaid::estimation
