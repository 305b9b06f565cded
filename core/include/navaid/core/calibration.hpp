#pragma once
// Sensor-rig calibration shared by readers, the simulator and the estimator.
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/geometry.hpp"

namespace navaid {

enum class DistortionModel { kNone, kRadialTangential, kEquidistant };

/// Intrinsics and extrinsics of one camera (Kalibr's names in comments).
struct CameraCalibration {
  std::string name = "cam0";
  int width = 0;   ///< resolution [px]
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< intrinsics
  DistortionModel distortion = DistortionModel::kNone;
  /// radtan: k1 k2 p1 p2 [k3]; equidistant: k1 k2 k3 k4.
  std::vector<double> distortion_coeffs;
  SE3 T_B_C;                 ///< camera to IMU body (inverse of Kalibr's T_cam_imu)
  double time_offset_s = 0;  ///< t_imu = t_cam + time_offset_s (Kalibr timeshift_cam_imu)
  double rate_hz = 0;        ///< nominal frame rate, 0 when unknown
  /// Depth camera properties (0 when the camera has no depth).
  double depth_min_m = 0, depth_max_m = 0;
  double depth_baseline_m = 0;       ///< stereo / structured-light baseline b
  double depth_disparity_sigma_px = 0;  ///< disparity noise sigma_d
};

/// Continuous-time IMU noise densities in Kalibr units.
struct ImuCalibration {
  double rate_hz = 0;
  double gyro_noise_density = 0;   ///< [rad/s/sqrt(Hz)]
  double gyro_random_walk = 0;     ///< [rad/s^2/sqrt(Hz)]
  double accel_noise_density = 0;  ///< [m/s^2/sqrt(Hz)]
  double accel_random_walk = 0;    ///< [m/s^3/sqrt(Hz)]
  SE3 T_B_I;                       ///< IMU to body (identity when the body is the IMU)
};

/// Geodetic origin of the local ENU frame.
struct GeodeticOrigin {
  double latitude_deg = 0, longitude_deg = 0, height_m = 0;  ///< WGS84, ellipsoidal height
};

struct RigCalibration {
  std::vector<CameraCalibration> cameras;
  std::optional<ImuCalibration> imu;
  Vec3 gps_lever_arm_B = Vec3::Zero();  ///< antenna position in the body frame [m]
  std::optional<double> gps_rate_hz;
  std::optional<double> mag_rate_hz;
};

}  // namespace navaid
