#pragma once
// What a path given on the command line holds, and reading it into a Recording.
//
// Detection (first match wins):
//   folder with recording.yaml                  -> navaid recording
//   folder with mav0/ (or imu0/ + cam0/)         -> EuRoC / ASL
//   folder with rgb.txt and depth.txt            -> TUM RGB-D
//   other folder with capture/trajectory files   -> collection (each member read on its own)
//   file starting with "#ROSBAG V2.0"             -> ROS 1 bag (docs/ros.md)
//   file whose first data lines are NMEA ($...)  -> NMEA capture
//   file whose first data line has 8 numbers     -> TUM trajectory
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "navaid/io/recording.hpp"

namespace navaid::io {

enum class InputKind { kNavaidRecording, kEuroc, kTumRgbd, kNmeaCapture, kTumTrajectory, kRosBag, kCollection };

std::string_view to_string(InputKind kind);
/// Names accepted by --format: navaid, euroc, tum-rgbd, nmea, tum-trajectory, ros-bag.
std::optional<InputKind> input_kind_from_string(std::string_view name);

/// Throws IoError naming the path and what was looked for when nothing fits.
InputKind detect_input(const std::filesystem::path& path);

/// Files of a collection folder that hold an NMEA capture or a TUM trajectory (by extension .log,
/// .nmea, .txt or .tum and by content), sorted by name. Other files (.chk, .md, .yaml) are skipped.
std::vector<std::filesystem::path> collection_members(const std::filesystem::path& folder);

/// Reads a single recording (not a collection) of the detected or forced kind. A ROS bag is read
/// with its topics found by type and its image messages counted, not extracted (read_ros_bag with
/// an image folder, as navaid convert and navaid run do, writes them as frames).
Recording read_input(const std::filesystem::path& path, std::optional<InputKind> kind = std::nullopt);

/// A navaid, EuRoC or TUM RGB-D recording (the kinds with camera frames); IoError naming the path
/// and saying it is not "a recording with <what>" for any other input (for a ROS bag: convert it
/// first).
Recording read_camera_recording(const std::filesystem::path& path, const std::string& what);

}  // namespace navaid::io
