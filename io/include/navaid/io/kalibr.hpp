#pragma once
// Kalibr calibration YAML: camchain-imucam (cameras + camera-IMU extrinsics) and IMU noise files.
// Validation is strict: a missing key, a value of the wrong type, a matrix of the wrong shape, a
// rotation that is not rigid (max |R^T R - I| > 1e-6 or det R < 0) or a negative noise raises
// ConfigError naming the file and the dotted key, e.g. "cam0.T_cam_imu". See docs/datasets.md.
#include <filesystem>

#include "navaid/core/calibration.hpp"

namespace navaid::io {

/// Reads cam0, cam1, ... (consecutive from cam0) of a Kalibr camchain-imucam file. Only the pinhole
/// camera model is supported; distortion radtan (4 or 5 coefficients), equidistant (4) or none.
/// T_B_C is the inverse of Kalibr's T_cam_imu; time_offset_s is timeshift_cam_imu (0 when absent).
/// The returned rig has no IMU (read it with read_kalibr_imu). rostopic, cam_overlaps and
/// T_cn_cnm1 are ignored.
RigCalibration read_kalibr_camchain(const std::filesystem::path& path);

/// Reads a Kalibr IMU file: either the output form (keys under "imu0", optional T_i_b) or the
/// flat input form (keys at the top level). Noise densities must be > 0, random walks >= 0 and
/// update_rate > 0. T_B_I is the inverse of T_i_b (identity when absent).
ImuCalibration read_kalibr_imu(const std::filesystem::path& path);

}  // namespace navaid::io
