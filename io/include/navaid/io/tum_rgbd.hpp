#pragma once
// TUM RGB-D benchmark folders (rgbd_dataset_freiburg*_*): rgb.txt, depth.txt, accelerometer.txt,
// groundtruth.txt and the rgb/ and depth/ PNG folders. See docs/datasets.md.
#include <filesystem>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/time.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::io {

/// rgb/depth pairs further apart than this (strictly) are not associated; TUM's associate.py
/// default max_difference.
constexpr Duration kTumAssociationTolerance = 20'000'000;  // 0.02 s
/// TUM depth PNGs hold 5000 units per metre.
constexpr double kTumDepthPngScale = 1.0 / 5000.0;

/// Which published intrinsics apply, chosen from the folder name.
enum class TumCamera { kFreiburg1, kFreiburg2, kFreiburg3, kRosDefault };

/// "rgbd_dataset_freiburg2_desk" -> kFreiburg2; kRosDefault when no "freiburgN" appears.
TumCamera tum_camera_from_name(std::string_view folder_name);
/// The colour camera of the TUM table (640x480, 30 Hz, T_B_C identity): freiburg1/2 with their
/// 5 radtan coefficients, freiburg3 without distortion, ROS default 525/525/319.5/239.5.
CameraCalibration tum_rgbd_camera(TumCamera camera);

/// One-to-one nearest-time association (the associate.py algorithm): all pairs with
/// |a[i] - b[j]| < tolerance, taken greedily by increasing time difference (ties by i, then j),
/// each index used at most once. Returns (i, j) pairs in increasing i. Both inputs ascending.
std::vector<std::pair<std::size_t, std::size_t>> associate_nearest(const std::vector<Timestamp>& a,
                                                                   const std::vector<Timestamp>& b,
                                                                   Duration tolerance);

/// Reads a TUM RGB-D folder. rgb.txt and depth.txt are required; accelerometer.txt (-> ImuSample
/// with has_gyro = false) and groundtruth.txt are read when present. Frames are the associated
/// rgb/depth pairs at the rgb time with depth_png_scale_m = 1/5000; unmatched images are counted
/// warnings. Throws IoError (file:line) on malformed lines, non-finite numbers, non-increasing
/// timestamps and listed image files that do not exist.
Recording read_tum_rgbd(const std::filesystem::path& folder);

}  // namespace navaid::io
