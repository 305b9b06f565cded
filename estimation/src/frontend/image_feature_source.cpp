#include "navaid/estimation/frontend/image_feature_source.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include <opencv2/core.hpp>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/config_schema.hpp"

namespace navaid::estimation {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kIntMin = std::numeric_limits<int>::min();
constexpr int kIntMax = std::numeric_limits<int>::max();

const CameraCalibration& find_camera(const RigCalibration& rig, const std::string& name) {
  if (rig.cameras.empty()) throw ConfigError("calibration", "cameras", "the front end needs a camera");
  if (name.empty()) return rig.cameras.front();
  for (const auto& c : rig.cameras)
    if (c.name == name) return c;
  throw ConfigError("calibration", "cameras", "no camera named '" + name + "'");
}

FeatureTracker make_tracker(const RigCalibration& rig, const FrontendConfig& config, const std::string& name) {
  return FeatureTracker(make_camera_model(find_camera(rig, name), "calibration"), config);
}

// Gyro rate at t, linear between samples and held outside them; `i` is the first sample after t.
Vec3 rate_at(const std::vector<ImuSample>& imu, std::size_t i, Timestamp t) {
  if (i == 0) return imu.front().gyro;
  if (i == imu.size()) return imu.back().gyro;
  const ImuSample& a = imu[i - 1];
  const ImuSample& b = imu[i];
  const double s = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return (1.0 - s) * a.gyro + s * b.gyro;
}

}  // namespace

namespace {

// The ranges are validate()'s (its errors are re-addressed to the key below), so the keys
// themselves accept any number.
const FrontendConfig kDefaults;
const ConfigKey<int> kMaxFeatures{"frontend.max_features", kDefaults.max_features, kIntMin, kIntMax,
                          "tracks kept per frame, >= 1"};
const ConfigKey<double> kMinDistancePx{"frontend.min_distance_px", kDefaults.min_distance_px, {-kInf, kInf},
                             "minimum distance between features [px], >= 0"};
const ConfigKey<double> kQualityLevel{"frontend.quality_level", kDefaults.quality_level, {-kInf, kInf},
                             "Shi-Tomasi quality relative to the best corner, in (0, 1)"};
const ConfigKey<int> kCornerBlockSize{"frontend.corner_block_size", kDefaults.corner_block_size, kIntMin, kIntMax,
                          "structure-tensor window [px], odd, >= 3"};
const ConfigKey<int> kDetectMinMissing{"frontend.detect_min_missing", kDefaults.detect_min_missing, kIntMin, kIntMax,
                          "detect only when at least this many tracks are missing, in [1, max_features]"};
const ConfigKey<int> kDepthEdgeMarginPx{"frontend.depth_edge_margin_px", kDefaults.depth_edge_margin_px, kIntMin, kIntMax,
                          "no new corners this near a depth discontinuity [px]; 0 = off"};
const ConfigKey<double> kDepthEdgeRelativeJump{"frontend.depth_edge_relative_jump", kDefaults.depth_edge_relative_jump, {-kInf, kInf},
                             "3x3 depth jump / nearer depth that marks an edge, > 0"};
const ConfigKey<int> kKltWindowPx{"frontend.klt_window_px", kDefaults.klt_window_px, kIntMin, kIntMax,
                          "KLT square search window side [px], odd, >= 5"};
const ConfigKey<int> kKltMaxLevel{"frontend.klt_max_level", kDefaults.klt_max_level, kIntMin, kIntMax,
                          "KLT pyramid levels above full resolution, in [0, 8]"};
const ConfigKey<int> kKltMaxIterations{"frontend.klt_max_iterations", kDefaults.klt_max_iterations, kIntMin, kIntMax,
                          "KLT iterations per level, >= 1"};
const ConfigKey<double> kKltEpsilon{"frontend.klt_epsilon", kDefaults.klt_epsilon, {-kInf, kInf},
                             "KLT iteration stop on the update [px], > 0"};
const ConfigKey<bool> kForwardBackwardCheck{"frontend.forward_backward_check", kDefaults.forward_backward_check, "track back and drop points that do not return"};
const ConfigKey<double> kFbThresholdPx{"frontend.fb_threshold_px", kDefaults.fb_threshold_px, {-kInf, kInf},
                             "forward-backward limit [px], > 0"};
const ConfigKey<int> kFbMaxLevel{"frontend.fb_max_level", kDefaults.fb_max_level, kIntMin, kIntMax,
                          "pyramid levels of the backward pass, in [0, 8]"};
const ConfigKey<int> kKltThreads{"frontend.klt_threads", kDefaults.klt_threads, kIntMin, kIntMax,
                          "threads a KLT pass splits its points over, in [1, 16] (same result)"};
const ConfigKey<int> kDriftCheckInterval{"frontend.drift_check_interval", kDefaults.drift_check_interval, kIntMin,
                                          kIntMax, "align each track to its birth patch every this many frames; 0 = off"};
const ConfigKey<double> kDriftMaxPx{"frontend.drift_max_px", kDefaults.drift_max_px, {-kInf, kInf},
                                    "drift check: corrections up to this [px] are applied, larger drop the track"};
const ConfigKey<bool> kRansac{"frontend.ransac", kDefaults.ransac, "fundamental-matrix RANSAC on undistorted points"};
const ConfigKey<double> kRansacThresholdPx{"frontend.ransac_threshold_px", kDefaults.ransac_threshold_px, {-kInf, kInf},
                             "RANSAC epipolar distance limit [px], > 0"};
const ConfigKey<double> kRansacConfidence{"frontend.ransac_confidence", kDefaults.ransac_confidence, {-kInf, kInf},
                             "RANSAC confidence, in (0, 1)"};
const ConfigKey<double> kBorderPx{"frontend.border_px", kDefaults.border_px, {-kInf, kInf},
                             "tracks closer than this to the image edge are dropped [px], >= 0"};
const ConfigKey<bool> kImuPrediction{"frontend.imu_prediction", kDefaults.imu_prediction, "predict KLT's start from the gyro rotation"};
const ConfigKey<int> kDepthPatchSize{"frontend.depth_patch_size", kDefaults.depth_patch_size, kIntMin, kIntMax,
                          "depth association patch: 3 or 5"};
const ConfigKey<double> kDepthMaxRelativeSpread{"frontend.depth_max_relative_spread", kDefaults.depth_max_relative_spread, {-kInf, kInf},
                             "(max - min) / median of the patch's valid depths, > 0"};
const ConfigKey<int> kDepthMinValid{"frontend.depth_min_valid", kDefaults.depth_min_valid, kIntMin, kIntMax,
                          "valid pixels needed in the depth patch, in [1, patch^2]"};
const ConfigKey<double> kKeyframeParallaxPx{"frontend.keyframe_parallax_px", kDefaults.keyframe_parallax_px, {-kInf, kInf},
                             "front-end keyframe: average parallax since the last keyframe [px], > 0"};
const ConfigKey<int> kKeyframeMinTracked{"frontend.keyframe_min_tracked", kDefaults.keyframe_min_tracked, kIntMin, kIntMax,
                          "front-end keyframe: fewer common tracks than this, >= 0"};

}  // namespace

ConfigSchema frontend_config_schema() {
  ConfigSchema s;
  s.add(kMaxFeatures);
  s.add(kMinDistancePx);
  s.add(kQualityLevel);
  s.add(kCornerBlockSize);
  s.add(kDetectMinMissing);
  s.add(kDepthEdgeMarginPx);
  s.add(kDepthEdgeRelativeJump);
  s.add(kKltWindowPx);
  s.add(kKltMaxLevel);
  s.add(kKltMaxIterations);
  s.add(kKltEpsilon);
  s.add(kForwardBackwardCheck);
  s.add(kFbThresholdPx);
  s.add(kFbMaxLevel);
  s.add(kKltThreads);
  s.add(kDriftCheckInterval);
  s.add(kDriftMaxPx);
  s.add(kRansac);
  s.add(kRansacThresholdPx);
  s.add(kRansacConfidence);
  s.add(kBorderPx);
  s.add(kImuPrediction);
  s.add(kDepthPatchSize);
  s.add(kDepthMaxRelativeSpread);
  s.add(kDepthMinValid);
  s.add(kKeyframeParallaxPx);
  s.add(kKeyframeMinTracked);
  return s;
}

FrontendConfig read_frontend_config(const Config& c) {
  FrontendConfig f;
  f.max_features = get(c, kMaxFeatures);
  f.min_distance_px = get(c, kMinDistancePx);
  f.quality_level = get(c, kQualityLevel);
  f.corner_block_size = get(c, kCornerBlockSize);
  f.detect_min_missing = get(c, kDetectMinMissing);
  f.depth_edge_margin_px = get(c, kDepthEdgeMarginPx);
  f.depth_edge_relative_jump = get(c, kDepthEdgeRelativeJump);
  f.klt_window_px = get(c, kKltWindowPx);
  f.klt_max_level = get(c, kKltMaxLevel);
  f.klt_max_iterations = get(c, kKltMaxIterations);
  f.klt_epsilon = get(c, kKltEpsilon);
  f.forward_backward_check = get(c, kForwardBackwardCheck);
  f.fb_threshold_px = get(c, kFbThresholdPx);
  f.fb_max_level = get(c, kFbMaxLevel);
  f.klt_threads = get(c, kKltThreads);
  f.drift_check_interval = get(c, kDriftCheckInterval);
  f.drift_max_px = get(c, kDriftMaxPx);
  f.ransac = get(c, kRansac);
  f.ransac_threshold_px = get(c, kRansacThresholdPx);
  f.ransac_confidence = get(c, kRansacConfidence);
  f.border_px = get(c, kBorderPx);
  f.imu_prediction = get(c, kImuPrediction);
  f.depth_patch_size = get(c, kDepthPatchSize);
  f.depth_max_relative_spread = get(c, kDepthMaxRelativeSpread);
  f.depth_min_valid = get(c, kDepthMinValid);
  f.keyframe_parallax_px = get(c, kKeyframeParallaxPx);
  f.keyframe_min_tracked = get(c, kKeyframeMinTracked);
  // One set of range rules (validate); its errors are re-addressed to the key and its origin.
  const std::string probe = "frontend";
  try {
    validate(f, probe);
  } catch (const ConfigError& e) {
    const std::string key = "frontend." + e.key();
    const std::string prefix = probe + ": key '" + e.key() + "': ";
    const std::string what = e.what();
    throw ConfigError(c.origin(key), key, what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
  }
  return f;
}

Eigen::Matrix3d integrate_gyro(const std::vector<ImuSample>& imu, Timestamp t0, Timestamp t1, const Vec3& gyro_bias) {
  Quat q = Quat::Identity();
  if (imu.empty() || t1 <= t0) return q.toRotationMatrix();
  const auto after = [&](Timestamp t) {
    return static_cast<std::size_t>(
        std::upper_bound(imu.begin(), imu.end(), t, [](Timestamp v, const ImuSample& s) { return v < s.t; }) -
        imu.begin());
  };
  // Breakpoints t0, the samples strictly inside (t0, t1), t1: the rate is linear between them, so
  // the mean of the end rates is the exact mean rate of each piece.
  std::size_t i = after(t0);
  Timestamp a = t0;
  Vec3 w_a = rate_at(imu, i, t0);
  while (a < t1) {
    const Timestamp b = (i < imu.size() && imu[i].t < t1) ? imu[i].t : t1;
    const std::size_t ib = (b == t1) ? after(t1) : i + 1;
    const Vec3 w_b = rate_at(imu, ib, b);
    const double dt = ns_to_seconds(b - a);
    q = (q * so3_exp((0.5 * (w_a + w_b) - gyro_bias) * dt)).normalized();
    a = b;
    w_a = w_b;
    i = ib;
  }
  return q.toRotationMatrix();
}

void set_opencv_threads(int threads) { cv::setNumThreads(threads); }

ImageFeatureSource::ImageFeatureSource(const RigCalibration& rig, const FrontendConfig& config,
                                       const std::string& camera_name, ImageLoader loader)
    : tracker_(make_tracker(rig, config, camera_name)),
      camera_name_(tracker_.camera().name()),
      R_B_C_(tracker_.camera().calibration().T_B_C.q.toRotationMatrix()),
      camera_to_imu_ns_(seconds_to_ns(tracker_.camera().calibration().time_offset_s)),
      loader_(std::move(loader)) {}

ImageFeatureSource::~ImageFeatureSource() = default;
ImageFeatureSource::ImageFeatureSource(ImageFeatureSource&&) noexcept = default;
ImageFeatureSource& ImageFeatureSource::operator=(ImageFeatureSource&&) noexcept = default;

void ImageFeatureSource::add_imu(const ImuSample& sample) {
  if (!sample.has_gyro) return;
  if (!gyro_.empty() && sample.t < gyro_.back().t)
    throw Error("front end: IMU sample at " + std::to_string(sample.t) + " ns after one at " +
                std::to_string(gyro_.back().t) + " ns (events must come in time order)");
  if (!gyro_.empty() && sample.t == gyro_.back().t) return;  // duplicate stamp: keep the first (as the back end)
  gyro_.push_back(sample);
}

std::optional<FeatureFrame> ImageFeatureSource::track(RgbdFrame frame) {
  if (frame.camera != camera_name_) return std::nullopt;
  last_load_ms_ = 0;
  if (frame.intensity.empty()) {
    if (!loader_)
      throw Error("front end: frame " + std::to_string(frame.index) + " of camera '" + frame.camera +
                  "' has no intensity loaded and no image loader is set");
    const auto start = std::chrono::steady_clock::now();
    loader_(frame);
    last_load_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

  const Timestamp t_imu = frame.t + camera_to_imu_ns_;
  last_rotation_.reset();
  if (tracker_.config().imu_prediction && previous_imu_t_ && !gyro_.empty() && t_imu > *previous_imu_t_) {
    // integrate_gyro gives R_Bprev_Bcur; directions map d_Ccur = R_C_B R_Bcur_Bprev R_B_C d_Cprev.
    const Eigen::Matrix3d R_prev_cur = integrate_gyro(gyro_, *previous_imu_t_, t_imu, gyro_bias_);
    last_rotation_ = R_B_C_.transpose() * R_prev_cur.transpose() * R_B_C_;
  }
  FeatureFrame out = tracker_.track(frame, last_rotation_);
  out.t = frame.t;
  out.camera = camera_name_;
  ++frames_tracked_;
  drift_totals_.checked += tracker_.stats().drift_checked;
  drift_totals_.corrected += tracker_.stats().drift_corrected;
  drift_totals_.dropped += tracker_.stats().rejected_drift;

  // Keep the last sample at or before this frame, so the next interval can interpolate from it.
  previous_imu_t_ = t_imu;
  const auto first_after =
      std::upper_bound(gyro_.begin(), gyro_.end(), t_imu, [](Timestamp v, const ImuSample& s) { return v < s.t; });
  if (first_after != gyro_.begin()) gyro_.erase(gyro_.begin(), first_after - 1);
  return out;
}

std::optional<SensorEvent> ImageFeatureSource::process(SensorEvent event) {
  if (auto* frame = std::get_if<RgbdFrame>(&event)) {
    auto features = track(std::move(*frame));
    if (!features) return std::nullopt;
    return SensorEvent(std::move(*features));
  }
  if (const auto* s = std::get_if<ImuSample>(&event)) add_imu(*s);
  return event;
}

}  // namespace navaid::estimation
