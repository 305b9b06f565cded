// A ROS bag written as a navaid recording (navaid convert, navaid run --recording X.bag).
#include <algorithm>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/io/kalibr.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/ros_bag.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;

// cam0 of a Kalibr camchain in place of the bag's camera (which only CameraInfo and /tf describe).
void apply_camchain(Recording& r, const fs::path& camchain) {
  const RigCalibration rig = read_kalibr_camchain(camchain);
  CameraCalibration c = rig.cameras.front();
  if (!r.calibration.cameras.empty()) {
    const CameraCalibration& bag = r.calibration.cameras.front();
    if (bag.width != c.width || bag.height != c.height)
      throw ConfigError(camchain.string(), "cam0.resolution",
                        "is " + std::to_string(c.width) + "x" + std::to_string(c.height) + " but the bag's images are " +
                            std::to_string(bag.width) + "x" + std::to_string(bag.height));
    c.rate_hz = bag.rate_hz;
    // A camchain has no depth model; the preset's (if any) stays.
    c.depth_min_m = bag.depth_min_m;
    c.depth_max_m = bag.depth_max_m;
    c.depth_baseline_m = bag.depth_baseline_m;
    c.depth_disparity_sigma_px = bag.depth_disparity_sigma_px;
  }
  c.name = r.frames.empty() ? c.name : r.frames.front().camera;
  r.calibration.cameras = {c};
}

}  // namespace

Recording convert_ros_bag(const fs::path& bag, const fs::path& folder, const RosBagConversion& conversion) {
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_empty(folder, ec)) {
    if (!conversion.overwrite)
      throw IoError(folder.string(), "exists and is not empty; pass --overwrite to replace its recording files");
    // Frame images of an earlier conversion would otherwise stay beside the new ones.
    for (const char* images : {"rgb", "depth", "labels", "confidence"}) fs::remove_all(folder / images, ec);
  }
  fs::create_directories(folder);
  RosBagReadOptions read = conversion.read;
  read.image_folder = folder;
  Recording r = read_ros_bag(bag, read);
  if (r.empty()) throw IoError(bag.string(), "holds no message of a sensor navaid reads (docs/ros.md lists them)");
  if (!conversion.camchain.empty()) apply_camchain(r, conversion.camchain);
  if (!r.frames.empty() && r.calibration.cameras.empty())
    throw IoError(bag.string(), "has images but no camera_info: give the camera's calibration with --camchain "
                                "(a Kalibr camchain-imucam file)");
  if (conversion.depth_max_m > 0) {
    if (conversion.depth_min_m < 0 || conversion.depth_min_m >= conversion.depth_max_m)
      throw ConfigError("--depth-range", "depth_range", "the range's minimum must be >= 0 and below its maximum");
    for (auto& c : r.calibration.cameras) c.depth_min_m = conversion.depth_min_m, c.depth_max_m = conversion.depth_max_m;
  }
  const bool has_depth = std::any_of(r.frames.begin(), r.frames.end(), [](const RgbdFrame& f) { return f.has_depth(); });
  if (has_depth && !r.calibration.cameras.empty() && r.calibration.cameras.front().depth_max_m <= 0)
    r.report.warn(bag.string(), "depth images but no working range: the front end leaves depth out (give --depth-range "
                                "MIN MAX or a camera model's preset, e.g. --bag-preset realsense-d455)");
  if (!conversion.imu_noise.empty()) {
    r.calibration.imu = read_kalibr_imu(conversion.imu_noise);
  } else if (!r.imu.empty()) {
    r.report.warn(bag.string(), "no IMU noise densities (a bag has none): the estimator needs them, give --imu-noise "
                                "(a Kalibr IMU file)");
  }
  if (!r.origin) r.origin = origin_from_fixes(r.gps);
  NavaidWriteOptions write;
  write.overwrite = true;  // the folder was checked above; the images are already in it
  write.images_in_place = true;
  write_navaid_recording(r, folder, write);
  return r;
}

}  // namespace navaid::io
