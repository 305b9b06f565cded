#pragma once
// Sensor messages: what every reader, the simulator and live drivers produce, in SI units.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/image.hpp"
#include "navaid/core/time.hpp"

namespace navaid {

/// One inertial sample in the IMU body frame B.
struct ImuSample {
  Timestamp t = 0;
  Vec3 gyro = Vec3::Zero();   ///< angular rate [rad/s]
  Vec3 accel = Vec3::Zero();  ///< specific force [m/s^2]
  bool has_gyro = true;       ///< false for accelerometer-only sources (TUM RGB-D)
};

/// One RGB-D frame. Images are loaded lazily by readers: the *_path members name the source files
/// and the image members stay empty until a consumer asks for pixels (see io::load_frame_images).
struct RgbdFrame {
  Timestamp t = 0;
  std::uint64_t index = 0;        ///< frame number within its recording
  std::string camera = "cam0";
  std::string intensity_path;     ///< intensity / colour image file (may be empty)
  std::string depth_path;         ///< 16-bit PNG depth file (may be empty)
  std::string labels_path;        ///< 8-bit semantic label PNG (may be empty)
  double depth_png_scale_m = 0.001;  ///< metres per 16-bit depth PNG unit (navaid: mm; TUM: 1/5000)
  ImageU8 intensity;              ///< grey levels (1 channel) or RGB (3 channels)
  ImageF32 depth;                 ///< metric depth along the optical axis [m]; 0 = invalid
  std::string confidence_path;    ///< 8-bit PNG, round(255 p) per pixel (may be empty)
  std::optional<ImageU8> labels;  ///< semantic class id per pixel
  /// Probability in [0, 1] that the segmentation gives the label of each pixel (same size as
  /// labels); with the producer's confusion model this gives the posterior over classes.
  std::optional<ImageF32> label_confidence;
  /// Per-pixel class probabilities, one channel per class of the label set.
  std::optional<ImageF32> class_probabilities;

  bool has_depth() const { return !depth_path.empty() || !depth.empty(); }
};

/// GNSS fix quality as reported by the receiver.
enum class GpsFixMode : std::uint8_t { kNoFix = 1, k2D = 2, k3D = 3 };

/// One GNSS position fix. Geodetic angles stay in degrees (GeographicLib's and every receiver's
/// convention; the names say so); everything else is SI.
struct GpsFix {
  Timestamp t = 0;
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;  ///< height above mean sea level (NaN when unknown, e.g. 2D fixes)
  double geoid_separation_m = 0.0;  ///< ellipsoid height = altitude_m + geoid_separation_m (NaN when unknown)
  GpsFixMode mode = GpsFixMode::k3D;
  int quality = 1;          ///< GGA quality indicator (1 GPS, 2 DGPS, 4 RTK fixed, ...)
  int satellites = 0;       ///< satellites used; -1 when the receiver does not say
  double hdop = 0.0;        ///< NaN when unknown
  /// Position covariance in the local ENU frame [m^2]; from GST when available, else HDOP-based.
  Mat3 covariance_enu = Mat3::Identity();
};

/// One magnetometer sample in the body frame B.
struct MagSample {
  Timestamp t = 0;
  Vec3 field = Vec3::Zero();  ///< magnetic flux density [T]
};

/// Ground-truth state of the body B in the world frame W.
struct GroundTruthState {
  Timestamp t = 0;
  SE3 T_W_B;
  std::optional<Vec3> v_W;   ///< velocity [m/s]
  std::optional<Vec3> b_g;   ///< gyro bias [rad/s]
  std::optional<Vec3> b_a;   ///< accelerometer bias [m/s^2]
};

/// One feature seen in one frame: a landmark/track id and where it appears.
struct FeatureObservation {
  std::uint64_t track_id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< distorted pixel coordinates [px], as a detected corner
  std::optional<double> depth_m;                 ///< depth along the optical axis [m], when measured
};

/// The features of one camera frame (feature-level simulation or an external front end), with
/// track ids strictly increasing.
struct FeatureFrame {
  Timestamp t = 0;
  std::string camera = "cam0";
  std::vector<FeatureObservation> features;
};

/// A ground-truth landmark (evaluation only): the point that feature track `id` observes.
struct Landmark {
  std::uint64_t id = 0;
  Vec3 p_W = Vec3::Zero();  ///< position in the world frame W [m]
};

using SensorEvent = std::variant<ImuSample, RgbdFrame, GpsFix, MagSample, FeatureFrame>;

inline Timestamp event_time(const SensorEvent& e) {
  return std::visit([](const auto& m) { return m.t; }, e);
}

}  // namespace navaid
