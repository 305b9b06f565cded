// How the window starts: from a still start (gravity from the mean accelerometer), or by the
// visual-inertial initialization over a window of keyframes (window SfM with HPnP or 3D-2D PnP,
// then visual-inertial alignment; docs/initialization.md, "In the estimator").
#include <cmath>
#include <map>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/initialization/visual_inertial_alignment.hpp"
#include "navaid/estimation/initialization/window_sfm.hpp"
#include "image_motion.hpp"
#include "impl.hpp"

namespace navaid::estimation {

namespace {

// Prior of the first state after a visual initialization: the alignment's velocities are good to
// a few cm/s (docs/initialization.md), looser than a still start's zero velocity.
constexpr double kVisualInitSigmaVelocity = 0.1;  // [m/s]

}  // namespace

StateEstimate SlidingWindowEstimator::Impl::initializing_estimate(Timestamp frame_t) const {
  StateEstimate e;
  e.t = frame_t;
  e.covariance = Mat15::Identity() * kUnknownVariance;
  e.mode = EstimatorMode::kInitializing;
  return e;
}

std::optional<StillGyro> SlidingWindowEstimator::Impl::still_gyro(const FeatureFrame& frame, Timestamp t, double span_s,
                                                                  double max_px) const {
  const std::optional<ImageMotion> motion = image_motion_over(recent_frames, frame, span_s);
  if (!motion || !motion->still(kMinStillTracks, max_px, cfg.pixel_sigma_px)) return std::nullopt;
  const Timestamp span = static_cast<Timestamp>(std::llround(span_s * 1e9));
  if (imu.empty() || imu.front().t > t - span || imu.back().t < t) return std::nullopt;
  const std::vector<ImuSample> samples = imu_samples_between(imu, t - span, t);
  if (samples.size() < 2) return std::nullopt;
  const double n = static_cast<double>(samples.size());
  StillGyro g;
  for (const auto& s : samples) g.mean += s.gyro;
  g.mean /= n;
  Vec3 spread = Vec3::Zero();
  for (const auto& s : samples) spread += (s.gyro - g.mean).cwiseAbs2();
  // The body did not turn, so the mean gyro is the bias (the earth's rate, <= 7.3e-5 rad/s, is
  // below the error of the mean). Its error: the samples' spread (vibration included) over sqrt(n)
  // times kStillBiasErrorFactor, never below white noise over the span, and the turn the image saw
  // (its tracks' coherent shift, at least that shift's own error of ~0.1 px).
  const Vec3 standard_error = (spread / (n - 1.0)).cwiseSqrt() / std::sqrt(n) * kStillBiasErrorFactor;
  const double white = imu_noise.gyro_noise_density / std::sqrt(span_s);
  const double seen_turn = std::max(motion->shift_px, 0.1) / (focal_px * span_s);
  g.sigma = (standard_error.cwiseMax(white).cwiseAbs2() + Vec3::Constant(seen_turn * seen_turn)).cwiseSqrt();
  return g;
}

bool SlidingWindowEstimator::Impl::still_start_possible(const FeatureFrame& frame, Timestamp t) const {
  const Timestamp still_ns = static_cast<Timestamp>(std::llround(cfg.still_duration_s * 1e9));
  if (imu.empty() || imu.front().t > t - still_ns || imu.back().t < t) return false;
  if (!still_gyro(frame, t, cfg.still_duration_s, cfg.still_max_motion_px)) return false;
  Vec3 accel = Vec3::Zero();
  const std::vector<ImuSample> samples = imu_samples_between(imu, t - still_ns, t);
  for (const auto& s : samples) accel += s.accel;
  accel /= static_cast<double>(samples.size());
  return std::abs(accel.norm() - kGravityW.norm()) <= kStillGravityTolerance;
}

StateEstimate SlidingWindowEstimator::Impl::initialize(const FeatureFrame& frame, Timestamp t) {
  const Timestamp still_ns = static_cast<Timestamp>(std::llround(cfg.still_duration_s * 1e9));
  const std::vector<ImuSample> samples = imu_samples_between(imu, t - still_ns, t);
  Vec3 accel = Vec3::Zero();
  for (const auto& s : samples) accel += s.accel;
  const double count = static_cast<double>(samples.size());
  accel /= count;
  if (!(accel.norm() > 1.0))
    throw Error("estimator: the mean specific force of the still start is " + std::to_string(accel.norm()) +
                " m/s^2; cannot find gravity");
  // The mean's own error across gravity tilts roll and pitch: a vibrating platform (a MAV's
  // motors, 0.2-1 m/s^2 of spread) measures gravity's direction to about a degree in 0.5 s.
  Vec3 accel_spread = Vec3::Zero();
  for (const auto& s : samples) accel_spread += (s.accel - accel).cwiseAbs2();
  const Vec3 accel_error = samples.size() >= 2 ? Vec3((accel_spread / (count - 1.0)).cwiseSqrt() / std::sqrt(count) *
                                                      kStillBiasErrorFactor)
                                                : Vec3::Zero();
  const Vec3 up = accel.normalized();
  const double tilt_sigma = (accel_error - up * up.dot(accel_error)).norm() / accel.norm();
  // A still window the camera confirms: the mean gyro is the bias.
  Vec3 b_g = Vec3::Zero();
  Vec3 sigma_b_g = Vec3::Constant(cfg.init_sigma_gyro_bias);
  const std::optional<StillGyro> still =
      cfg.still_gyro_bias ? still_gyro(frame, t, cfg.still_duration_s, cfg.still_max_motion_px) : std::nullopt;
  if (still) {
    b_g = still->mean;
    sigma_b_g = still->sigma;
    ++stats.still_gyro_bias_initializations;
  }
  // At rest the accelerometer measures -g: R_W_B accel points up. Yaw is unobservable: 0.
  const Quat q_up = Quat::FromTwoVectors(accel, Vec3::UnitZ());
  const Vec3 rpy = rpy_from_quat(q_up);
  const Quat q = quat_from_rpy(rpy.x(), rpy.y(), 0.0);

  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  s->keyframe = true;
  pose_to_block(SE3(q, Vec3::Zero()), s->pose);
  for (int i = 0; i < 3; ++i) s->speed_bias[3 + i] = b_g[i];
  Mat15 P0 = initial_covariance(q, tilt_sigma);
  P0.block<3, 3>(9, 9) = sigma_b_g.cwiseAbs2().asDiagonal();
  state_prior = std::make_shared<StatePriorFactor>(s->T_W_B(), Vec3::Zero(), b_g, Vec3::Zero(), P0);
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
  stats.initialized_at_s = ns_to_seconds(t);
  return estimate_of(*window.back(), frame.t, EstimatorMode::kInitializing, P0);
}

StateEstimate SlidingWindowEstimator::Impl::collect_for_visual_initialization(const FeatureFrame& frame, Timestamp t) {
  // Keyframes gather (chosen by parallax like later ones) with IMU preintegrated between them at
  // zero bias; once the window is full, every new keyframe triggers an attempt, and the oldest
  // keyframe is dropped (nothing to marginalize yet).
  if (!window.empty() && t <= window.back()->t)
    throw Error("estimator: feature frames must have increasing time stamps");
  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  if (!window.empty()) {
    if (imu.empty() || imu.front().t > window.back()->t) return initializing_estimate(frame.t);
    s->imu = ImuPreintegration::between(imu, window.back()->t, t, imu_noise, Vec3::Zero(), Vec3::Zero());
  }
  window.push_back(std::move(s));
  WindowState& newest = *window.back();
  add_observations(newest.id, frame);
  if (cfg.use_gps) attach_gps(newest);  // drops the fixes of the frames before the initialization
  const bool keyframe =
      window.size() == 1 || decide_keyframe(*window[window.size() - 2], newest, frame.features.size());
  if (!keyframe) {
    tracks.remove_frame(newest.id);
    window.pop_back();
    return initializing_estimate(frame.t);
  }
  newest.keyframe = true;
  newest.gps.reset();
  if (static_cast<int>(window.size()) > cfg.window_size) {
    tracks.remove_frame(window.front()->id);
    window.pop_front();
    window.front()->imu.reset();
  }
  if (static_cast<int>(window.size()) < cfg.window_size || !visual_initialization())
    return initializing_estimate(frame.t);
  last_estimate = solve_newest(frame, /*keyframe=*/true);
  return *last_estimate;
}

bool SlidingWindowEstimator::Impl::visual_initialization() {
  ++stats.initialization_attempts;
  auto fail = [&](const std::string& why) {
    ++stats.initialization_failures;
    stats.last_initialization_failure = why;
    return false;
  };
  std::map<std::uint64_t, std::size_t> index;
  for (std::size_t k = 0; k < window.size(); ++k) index[window[k]->id] = k;
  std::vector<SfmKeyframe> keyframes(window.size());
  for (const auto& [id, track] : tracks.tracks())
    for (const auto& o : track.observations)
      keyframes[index.at(o.frame_id)].observations.push_back({id, o.m, o.depth_m});

  WindowSfmOptions so;
  so.method = init_method == InitializationMethod::kPnp ? PoseChangeMethod::kPnp : PoseChangeMethod::kHybrid;
  so.focal_px = focal_px;
  so.pixel_sigma_px = cfg.pixel_sigma_px;
  if (sigma_lambda > 0) so.inverse_depth_sigma = sigma_lambda;
  const WindowSfm sfm = solve_window_sfm(keyframes, so);
  if (!sfm.success) return fail("window SfM: " + sfm.failure);

  std::vector<Timestamp> times;
  std::vector<ImuPreintegration> preintegrations;
  for (std::size_t k = 0; k < window.size(); ++k) {
    times.push_back(window[k]->t);
    if (k > 0) preintegrations.push_back(*window[k]->imu);
  }
  VisualInertialAlignmentOptions ao;
  ao.estimate_scale = sfm.up_to_scale;
  const VisualInertialAlignment a =
      align_visual_inertial(times, sfm.T_l_C, pose_from_block(extrinsic), preintegrations, ao);
  if (!a.success) return fail("visual-inertial alignment: " + a.failure);

  for (std::size_t k = 0; k < window.size(); ++k) {
    WindowState& s = *window[k];
    pose_to_block(a.T_W_B[k], s.pose);
    const Vec3& v = a.v_W[k];
    s.speed_bias[0] = v.x(), s.speed_bias[1] = v.y(), s.speed_bias[2] = v.z();
    for (int i = 0; i < 3; ++i) s.speed_bias[3 + i] = a.gyro_bias[i], s.speed_bias[6 + i] = a.accel_bias[i];
    if (k > 0) s.imu = a.preintegrations[k - 1];
  }
  for (auto& [id, track] : tracks.tracks()) {
    track.initialized = false;
    const auto p = sfm.points_l.find(id);
    const WindowState* anchor = state(track.anchor().frame_id);
    if (p == sfm.points_l.end() || !anchor) continue;
    const Vec3 P_W = a.T_W_l * (a.scale * p->second);
    const double z = (T_W_C(*anchor).inverse() * P_W).z();
    if (z > kMinFeatureDepth && z < kMaxFeatureDepth) {
      track.landmark[0] = track.anchor().m.x();
      track.landmark[1] = track.anchor().m.y();
      track.inverse_depth() = 1.0 / z;
      track.initialized = true;
    }
  }
  // The first keyframe defines W (position and yaw); roll, pitch, velocity and biases come from
  // the alignment.
  const WindowState& first = *window.front();
  Mat15 P0 = initial_covariance(first.T_W_B().q);
  P0.block<3, 3>(6, 6) = Mat3::Identity() * kVisualInitSigmaVelocity * kVisualInitSigmaVelocity;
  state_prior = std::make_shared<StatePriorFactor>(first.T_W_B(), first.v(), first.b_g(), first.b_a(), P0);
  state_prior_id = first.id;
  initialized = true;
  stats.initialized_at_s = ns_to_seconds(window.back()->t);
  return true;
}

}  // namespace navaid::estimation
