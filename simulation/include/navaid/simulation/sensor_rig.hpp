#pragma once
// Sensor presets (camera + IMU of real devices) and mounts (where the rig sits on the walker).
//
// Body frame B = the IMU frame of the rig, x forward, y left, z up (walker_trajectory.hpp). The
// walker trajectory is generated for B directly: a mount sets its height above ground and the
// motion it adds (head scanning, cane sweep) through WalkerConfig, and the camera extrinsic T_B_C
// (optical frame: z forward, x right, y down) with the camera pitched down by camera_pitch_rad.
// Values are documented, with their sources, in docs/simulate.md.
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::simulation {

/// An RGB-D camera with its built-in IMU, as calibration values (T_B_C left at identity).
struct SensorPreset {
  std::string name;
  CameraCalibration camera;
  ImuCalibration imu;
};

/// Known presets: "d455" (Intel RealSense D455-like, eLabrador) and "structure-core"
/// (Occipital Structure Core-like, W-ROMA RGBD-VIO). ConfigError (key `key`) listing the names
/// when unknown.
SensorPreset sensor_preset(std::string_view name, const std::string& key = "sensor.preset");
std::vector<std::string> sensor_preset_names();

struct Mount {
  std::string name;
  std::string default_sensor;   ///< sensor preset of the paper that uses this mount
  double height_m = 1.7;        ///< B above ground
  double camera_pitch_rad = 0;  ///< camera tilted down by this angle about B's y axis
  Vec3 t_B_C = Vec3::Zero();    ///< camera centre in B [m]
  Vec3 gps_lever_arm_B = Vec3::Zero();  ///< GNSS antenna in B [m]
  double scan_amplitude_rad = 0;        ///< yaw scanning of the rig (head turns, cane sweep)
  double scan_period_s = 4.0;

  /// Camera-to-body transform: optical axis along B x, pitched down, translated by t_B_C.
  SE3 T_B_C() const;
  /// The walker configuration with this mount's height and scanning applied.
  WalkerConfig apply(WalkerConfig walker) const;
};

/// Known mounts: "head" (helmet, eLabrador), "cane" (handle, BYU augmented cane / Smart Cane),
/// "hand" (hand-held, W-ROMA). ConfigError (key `key`) listing the names when unknown.
Mount mount_preset(std::string_view name, const std::string& key = "mount");
std::vector<std::string> mount_names();

}  // namespace navaid::simulation
