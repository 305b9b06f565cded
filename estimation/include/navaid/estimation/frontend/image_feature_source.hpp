#pragma once
// Image recordings into the back end: an ImageFeatureSource owns a FeatureTracker for the
// estimator's camera and turns that camera's RgbdFrames into FeatureFrames, in event order, so
// that the sliding-window estimator (which consumes FeatureFrames only) runs on images.
//
//  - Frames of other cameras are skipped; the FeatureFrame keeps the frame's time stamp.
//  - Pixels: a frame whose intensity is not loaded is loaded by the ImageLoader given at
//    construction (the estimation room reads no files; navaid run passes io's readers). The
//    frame is taken by value and its pixels die with it, so memory stays flat over a recording.
//  - KLT prediction (FrontendConfig::imu_prediction): the gyro rates fed through add_imu() are
//    integrated from the previous frame to this one (IMU time = camera time + the camera's
//    time_offset_s) and turned into the camera rotation R_cur_prev = R_C_B ΔR_B R_B_C.
//
// Single-threaded and deterministic: the same events give the same FeatureFrames.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/estimation/frontend/feature_tracker.hpp"
#include "navaid/estimation/frontend/frontend_config.hpp"

namespace navaid::estimation {

/// Reads `frontend.<field>` for every FrontendConfig field (same names, FrontendConfig's
/// defaults for absent keys) and validates the result; ConfigError names the file (or --set)
/// and the `frontend.` key with its allowed range.
FrontendConfig read_frontend_config(const Config& config);

/// Rotation R_B0_B1 of the body from t0 to t1 (d_B0 = R_B0_B1 d_B1) by integrating
/// (gyro - gyro_bias) over `imu` (time-ordered, gyro in the body frame): rates are linear between
/// samples (exact for rates that are linear in time about a fixed axis), held at the first / last
/// sample outside them. Identity when t1 <= t0 or `imu` is empty.
Eigen::Matrix3d integrate_gyro(const std::vector<ImuSample>& imu, Timestamp t0, Timestamp t1,
                               const Vec3& gyro_bias = Vec3::Zero());

/// Sets the number of OpenCV worker threads of the whole process (cv::setNumThreads; 0 = run
/// OpenCV's parallel loops on the calling thread). OpenCV's parallel loops make the front end's
/// output vary from run to run in the last bits (measured: tracks and estimates differ between
/// replays of one recording), so a deterministic replay sets 1. The tracker itself sets nothing
/// global; this is for the program that owns the process (navaid run).
void set_opencv_threads(int threads);

class ImageFeatureSource {
 public:
  /// Fills the pixels of a frame (at least its intensity; depth when it has some).
  using ImageLoader = std::function<void(RgbdFrame&)>;

  /// Tracks camera `camera_name` of `rig` (its first camera when empty, as the estimator).
  /// ConfigError when the rig has no such camera or the camera or front-end config is unusable.
  ImageFeatureSource(const RigCalibration& rig, const FrontendConfig& config, const std::string& camera_name = {},
                     ImageLoader loader = {});
  ~ImageFeatureSource();
  ImageFeatureSource(ImageFeatureSource&&) noexcept;
  ImageFeatureSource& operator=(ImageFeatureSource&&) noexcept;
  ImageFeatureSource(const ImageFeatureSource&) = delete;
  ImageFeatureSource& operator=(const ImageFeatureSource&) = delete;

  /// One IMU sample for the KLT prediction; samples must come in time order (Error otherwise).
  /// Samples without gyro data are ignored.
  void add_imu(const ImuSample& sample);
  /// Gyro bias subtracted before integrating (e.g. the back end's latest estimate).
  void set_gyro_bias(const Vec3& gyro_bias) { gyro_bias_ = gyro_bias; }

  /// The frame's features, or nullopt for another camera's frame. Error when the frame has no
  /// intensity and no loader is set, or when its images do not fit the camera (FeatureTracker).
  std::optional<FeatureFrame> track(RgbdFrame frame);

  /// Feeds any event in time order and returns what the back end should get: the FeatureFrame
  /// of a tracked RgbdFrame, nothing for other cameras' frames, every other event unchanged
  /// (IMU samples also go to add_imu()).
  std::optional<SensorEvent> process(SensorEvent event);

  /// Of the last frame tracked: the tracker's statistics, the time spent loading its images [ms],
  /// and the camera rotation R_cur_prev used for the prediction (nullopt: first frame, prediction
  /// off or no gyro data yet).
  const FrontendStats& stats() const { return tracker_.stats(); }
  double last_load_ms() const { return last_load_ms_; }
  const std::optional<Eigen::Matrix3d>& last_rotation() const { return last_rotation_; }

  const std::string& camera_name() const { return camera_name_; }
  std::size_t frames_tracked() const { return frames_tracked_; }
  /// The drift check's counts over every frame tracked (FrontendStats' drift_* summed).
  struct DriftTotals {
    std::size_t checked = 0, corrected = 0, dropped = 0;
  };
  const DriftTotals& drift_totals() const { return drift_totals_; }

 private:
  FeatureTracker tracker_;
  std::string camera_name_;
  Eigen::Matrix3d R_B_C_ = Eigen::Matrix3d::Identity();
  Timestamp camera_to_imu_ns_ = 0;
  ImageLoader loader_;
  std::vector<ImuSample> gyro_;  // samples from just before the previous frame on
  Vec3 gyro_bias_ = Vec3::Zero();
  std::optional<Timestamp> previous_imu_t_;  // IMU time of the previous frame
  std::optional<Eigen::Matrix3d> last_rotation_;
  double last_load_ms_ = 0;
  std::size_t frames_tracked_ = 0;
  DriftTotals drift_totals_;
};

}  // namespace navaid::estimation
