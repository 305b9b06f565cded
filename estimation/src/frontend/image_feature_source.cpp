#include "navaid/estimation/frontend/image_feature_source.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include <opencv2/core.hpp>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::estimation {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr long long kIntMin = std::numeric_limits<int>::min();
constexpr long long kIntMax = std::numeric_limits<int>::max();

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

FrontendConfig read_frontend_config(const Config& c) {
  FrontendConfig f;
  const auto get_int = [&](const char* name, int fallback) {
    return static_cast<int>(c.get_int(std::string("frontend.") + name, fallback, kIntMin, kIntMax));
  };
  const auto get_double = [&](const char* name, double fallback) {
    return c.get_double(std::string("frontend.") + name, fallback, {-kInf, kInf});
  };
  f.max_features = get_int("max_features", f.max_features);
  f.min_distance_px = get_double("min_distance_px", f.min_distance_px);
  f.quality_level = get_double("quality_level", f.quality_level);
  f.corner_block_size = get_int("corner_block_size", f.corner_block_size);
  f.detect_min_missing = get_int("detect_min_missing", f.detect_min_missing);
  f.depth_edge_margin_px = get_int("depth_edge_margin_px", f.depth_edge_margin_px);
  f.depth_edge_relative_jump = get_double("depth_edge_relative_jump", f.depth_edge_relative_jump);
  f.klt_window_px = get_int("klt_window_px", f.klt_window_px);
  f.klt_max_level = get_int("klt_max_level", f.klt_max_level);
  f.klt_max_iterations = get_int("klt_max_iterations", f.klt_max_iterations);
  f.klt_epsilon = get_double("klt_epsilon", f.klt_epsilon);
  f.forward_backward_check = c.get_bool("frontend.forward_backward_check", f.forward_backward_check);
  f.fb_threshold_px = get_double("fb_threshold_px", f.fb_threshold_px);
  f.fb_max_level = get_int("fb_max_level", f.fb_max_level);
  f.klt_threads = get_int("klt_threads", f.klt_threads);
  f.ransac = c.get_bool("frontend.ransac", f.ransac);
  f.ransac_threshold_px = get_double("ransac_threshold_px", f.ransac_threshold_px);
  f.ransac_confidence = get_double("ransac_confidence", f.ransac_confidence);
  f.border_px = get_double("border_px", f.border_px);
  f.imu_prediction = c.get_bool("frontend.imu_prediction", f.imu_prediction);
  f.depth_patch_size = get_int("depth_patch_size", f.depth_patch_size);
  f.depth_max_relative_spread = get_double("depth_max_relative_spread", f.depth_max_relative_spread);
  f.depth_min_valid = get_int("depth_min_valid", f.depth_min_valid);
  f.keyframe_parallax_px = get_double("keyframe_parallax_px", f.keyframe_parallax_px);
  f.keyframe_min_tracked = get_int("keyframe_min_tracked", f.keyframe_min_tracked);
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
