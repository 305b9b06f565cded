#pragma once
// A run folder as a ROS 1 bag for RViz (navaid export --run RUN --bag OUT.bag; docs/ros.md):
//   /tf_static            body -> camera (T_B_C of the recording's calibration)
//   /tf                   world -> body, one per estimate
//   /navaid/pose          geometry_msgs/PoseWithCovarianceStamped, one per estimate (the position
//                         and rotation blocks of the estimate's covariance, rotation about world axes)
//   /navaid/path          nav_msgs/Path, the trajectory so far, at path_rate_hz and at the end
//   /navaid/map           sensor_msgs/PointCloud2 of map/map.ply at the end (x y z rgb class_id
//                         probability occupancy), coloured by class
//   /navaid/markers       visualization_msgs/MarkerArray: obstacles (occupied voxels whose class
//                         blocks the way), each plan of plans.csv as a line, each directional cue of
//                         cues.csv as an arrow from the user's position
// Frames: "world" (W), "body" (B), "camera" (C). ROS headers stay in the source file.
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>

namespace navaid::experiments {

struct RunBagExportOptions {
  std::filesystem::path run;        ///< the run folder (estimates.csv, summary.json, map/, plans.csv, cues.csv)
  std::filesystem::path bag;        ///< the bag to write (replaced)
  std::filesystem::path recording;  ///< for T_B_C; empty = the one summary.json names
  std::string compression = "lz4";  ///< none, bz2 or lz4 chunks
  double path_rate_hz = 1.0;        ///< /navaid/path messages per second of the run
  std::size_t path_max_poses = 1000;  ///< a path message holds at most this many poses (evenly thinned)
};

/// Messages written per topic.
using RunBagExportCounts = std::map<std::string, std::size_t>;

/// Writes the bag. Throws UsageError for bad options, IoError naming the file for a run folder
/// without estimates.csv, an unreadable part, or a recording that cannot be found.
RunBagExportCounts export_run_bag(const RunBagExportOptions& options);

}  // namespace navaid::experiments
