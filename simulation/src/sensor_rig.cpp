#include "navaid/simulation/sensor_rig.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {

constexpr double kDeg = M_PI / 180.0;

CameraCalibration vga_camera(double fx, double min_m, double max_m, double baseline_m, double sigma_d_px) {
  CameraCalibration c;
  c.name = "cam0";
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = fx;
  c.cx = 319.5;
  c.cy = 239.5;
  c.distortion = DistortionModel::kNone;  // the devices deliver rectified, depth-aligned images
  c.rate_hz = 30.0;
  c.depth_min_m = min_m;
  c.depth_max_m = max_m;
  c.depth_baseline_m = baseline_m;
  c.depth_disparity_sigma_px = sigma_d_px;
  return c;
}

ImuCalibration imu(double rate_hz, double gyro_nd, double gyro_rw, double accel_nd, double accel_rw) {
  ImuCalibration i;
  i.rate_hz = rate_hz;
  i.gyro_noise_density = gyro_nd;
  i.gyro_random_walk = gyro_rw;
  i.accel_noise_density = accel_nd;
  i.accel_random_walk = accel_rw;
  return i;
}

}  // namespace

std::vector<std::string> sensor_preset_names() { return {"d455", "structure-core"}; }

SensorPreset sensor_preset(std::string_view name, const std::string& key) {
  // D455: 95 mm stereo baseline, ~87 deg HFOV depth at 640x480 (fx ~ 385 px), usable 0.4-6 m,
  // BMI055 IMU at 200 Hz. Structure Core: 640x480 at 30 Hz, depth 0.3-5 m, BMI085 IMU at 500 Hz
  // (the W-ROMA sequences); structured-light baseline ~ 65 mm, fx ~ 460 px.
  // IMU densities: datasheet white noise, random walks as typical Kalibr calibrations of these
  // MEMS parts.
  if (name == "d455") return {"d455", vga_camera(385.0, 0.4, 6.0, 0.095, 0.08), imu(200.0, 2.4e-4, 2.0e-5, 1.5e-3, 3.0e-4)};
  if (name == "structure-core")
    return {"structure-core", vga_camera(460.0, 0.3, 5.0, 0.065, 0.1), imu(500.0, 2.4e-4, 2.0e-5, 1.2e-3, 3.0e-4)};
  throw ConfigError("", key, fmt::format("unknown sensor preset '{}'; known: {}", name, fmt::join(sensor_preset_names(), ", ")));
}

std::vector<std::string> mount_names() { return {"head", "cane", "hand"}; }

Mount mount_preset(std::string_view name, const std::string& key) {
  Mount m;
  m.name = std::string(name);
  if (name == "head") {  // helmet camera at eye height, looking slightly down, head scanning
    m.default_sensor = "d455";
    m.height_m = 1.70;
    m.camera_pitch_rad = 15.0 * kDeg;
    m.t_B_C = Vec3(0.0, 0.0, 0.0);
    m.gps_lever_arm_B = Vec3(-0.05, 0.0, 0.12);  // phone/receiver on top of the helmet
    m.scan_amplitude_rad = 0.3;
    m.scan_period_s = 4.0;
  } else if (name == "cane") {  // camera on the cane shaft below the handle, looking down ahead
    m.default_sensor = "d455";
    m.height_m = 0.80;
    m.camera_pitch_rad = 25.0 * kDeg;
    m.t_B_C = Vec3(0.02, 0.0, -0.01);
    m.gps_lever_arm_B = Vec3(-0.10, 0.0, 0.10);
    m.scan_amplitude_rad = 0.15;  // the cane sweeps left-right once per two steps
    m.scan_period_s = 1.1;
  } else if (name == "hand") {  // hand-held rig at chest height (RGBD-VIO data collection)
    m.default_sensor = "structure-core";
    m.height_m = 1.20;
    m.camera_pitch_rad = 10.0 * kDeg;
    m.t_B_C = Vec3(0.01, -0.03, 0.0);
    m.gps_lever_arm_B = Vec3(0.0, 0.0, 0.05);
    m.scan_amplitude_rad = 0.12;
    m.scan_period_s = 6.0;
  } else {
    throw ConfigError("", key, fmt::format("unknown mount '{}'; known: {}", name, fmt::join(mount_names(), ", ")));
  }
  return m;
}

SE3 Mount::T_B_C() const {
  // Camera looking along B x: z_C = x_B, x_C = -y_B, y_C = -z_B; then pitched down about y_B.
  Mat3 R_base;
  R_base.col(0) = Vec3(0, -1, 0);
  R_base.col(1) = Vec3(0, 0, -1);
  R_base.col(2) = Vec3(1, 0, 0);
  const Mat3 R_pitch = Eigen::AngleAxisd(camera_pitch_rad, Vec3::UnitY()).toRotationMatrix();
  return SE3(Mat3(R_pitch * R_base), t_B_C);
}

WalkerConfig Mount::apply(WalkerConfig walker) const {
  walker.mount_height_m = height_m;
  walker.scan_amplitude_rad = scan_amplitude_rad;
  walker.scan_period_s = scan_period_s;
  return walker;
}

}  // namespace navaid::simulation
