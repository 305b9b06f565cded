#include "navaid/experiments/device_requirements.hpp"

#include <algorithm>

namespace navaid::experiments {

using runtime::DeviceSpec;
using runtime::GuidanceKind;

std::vector<std::string> missing_for_device(const DeviceSpec& spec, const io::Recording& recording,
                                            const std::filesystem::path& recording_dir) {
  std::vector<std::string> missing;
  if (recording.imu.empty()) missing.push_back("IMU samples (the estimator needs them)");
  if (recording.frames.empty()) missing.push_back("image frames (the device maps and guides from them)");
  const bool any_depth = std::any_of(recording.frames.begin(), recording.frames.end(),
                                     [](const RgbdFrame& f) { return f.has_depth(); });
  if (spec.needs_depth && !recording.frames.empty() && !any_depth)
    missing.push_back("depth images (device " + spec.name + " needs them: device.needs; set device.needs=[] to run without, degraded)");
  if (spec.needs_gps && recording.gps.empty())
    missing.push_back("GPS fixes (device " + spec.name + " follows a route registered to GPS)");
  const bool simulated = std::filesystem::is_regular_file(recording_dir / "simulation.yaml");
  if (spec.guidance == GuidanceKind::kRoute && spec.route_osm.empty() && !simulated)
    missing.push_back("a street map: set device.route.osm=FILE and device.route.to=LAT,LON (only a simulated "
                      "recording brings its own streets)");
  if (spec.guidance == GuidanceKind::kRoute && !spec.route_osm.empty() && !spec.route_to && !simulated)
    missing.push_back("a destination: set device.route.to=LAT,LON");
  if (spec.guidance == GuidanceKind::kWalkingPath && !spec.goal_start_frame_m && !simulated)
    missing.push_back("a goal: set device.goal_start_frame_m=FORWARD,LEFT (metres from the start pose)");
  return missing;
}

}  // namespace navaid::experiments
