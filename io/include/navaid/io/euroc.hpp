#pragma once
// EuRoC / ASL dataset folders (<sequence>/mav0/{imu0,cam0,cam1,state_groundtruth_estimate0}).
// See docs/datasets.md for what is read, what is ignored and which problems are errors.
#include <filesystem>
#include <optional>
#include <string>

#include "navaid/core/calibration.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::io {

/// Reads an EuRoC/ASL sequence; `folder` is the sequence folder (holding mav0/) or mav0 itself.
/// - imu0/data.csv (ns, gyro xyz [rad/s], accel xyz [m/s^2]) and imu0/sensor.yaml (noise, T_BS);
/// - cam0/, cam1/, ... (consecutive): data.csv (ns, file name) and sensor.yaml; every listed
///   image must exist under camN/data/. Frames carry intensity_path only (no depth), their
///   `camera` is "camN" and their `index` is the row number within that camera's data.csv.
///   Frames of all cameras are merged in time order (cam0 before cam1 at equal times);
/// - state_groundtruth_estimate0/data.csv when present (pose with w-first quaternion, and when the
///   row has all 17 columns velocity, gyro bias and accel bias).
/// leica0/, pointcloud0/ and body.yaml are ignored. Malformed data throws IoError (file:line);
/// malformed calibration throws ConfigError (file + key).
/// `imu_calibration`: an IMU sensor.yaml to use instead of imu0/sensor.yaml (for folders that
/// ship the samples without it).
Recording read_euroc(const std::filesystem::path& folder,
                     const std::optional<std::filesystem::path>& imu_calibration = std::nullopt);

/// A camera sensor.yaml in EuRoC's own format (T_BS {rows, cols, data}, rate_hz, resolution,
/// camera_model pinhole, intrinsics [fu fv cu cv], distortion_model, distortion_coefficients).
CameraCalibration read_euroc_camera_yaml(const std::filesystem::path& path, const std::string& name);
/// An IMU sensor.yaml in EuRoC's format (T_BS, rate_hz, Kalibr-named noise densities).
ImuCalibration read_euroc_imu_yaml(const std::filesystem::path& path);

}  // namespace navaid::io
