#pragma once
// The ROS bag options shared by navaid convert and navaid run (docs/ros.md): which topic plays
// which role, and the calibration a bag cannot hold.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/io/ros_bag.hpp"

namespace navaid::cli {

struct BagOptions {
  std::vector<std::string> topics;  // ROLE=TOPIC
  std::filesystem::path topics_file;
  std::string preset;
  std::filesystem::path camchain, imu_noise;
  double depth_pair_window_s = 0.0;
  std::vector<double> depth_range;

  void add_to(CLI::App& cmd) {
    cmd.add_option("--topic", topics,
                   "ROS bag: the topic of a role, ROLE=TOPIC (roles: imu, gyro, accel, image, depth, camera_info, gps, "
                   "mag, groundtruth); repeatable. Unnamed roles are found by message type");
    cmd.add_option("--topics", topics_file, "ROS bag: a YAML file of role: topic (and preset: NAME)")
        ->check(CLI::ExistingFile);
    cmd.add_option("--bag-preset", preset, "ROS bag: a driver's topic names (realsense, realsense-d435i, realsense-d455 with their depth baselines, "
                   "structure-core)");
    cmd.add_option("--camchain", camchain, "ROS bag: Kalibr camchain-imucam file for cam0 (intrinsics, T_cam_imu)")
        ->check(CLI::ExistingFile);
    cmd.add_option("--imu-noise", imu_noise, "ROS bag: Kalibr IMU file with the noise densities")
        ->check(CLI::ExistingFile);
    cmd.add_option("--depth-pair-window", depth_pair_window_s,
                   "ROS bag: pair a depth image with the intensity image nearest in time within this many seconds "
                   "(default: half the frame period)")
        ->check(CLI::PositiveNumber);
    cmd.add_option("--depth-range", depth_range, "ROS bag: the depth camera's working range MIN MAX [m]")
        ->expected(2);
  }

  bool given() const {
    return !topics.empty() || !topics_file.empty() || !preset.empty() || !camchain.empty() || !imu_noise.empty() ||
           depth_pair_window_s > 0 || !depth_range.empty();
  }

  io::RosBagConversion conversion() const {
    io::RosBagConversion c;
    if (!topics_file.empty()) {
      const auto choice = io::read_ros_bag_topics_file(topics_file);
      c.read.topics = choice.topics;
      c.read.preset = choice.preset;
    }
    if (!preset.empty()) {
      io::ros_bag_preset(preset);  // checks the name
      c.read.preset = preset;
    }
    for (const auto& assignment : topics) {
      const auto eq = assignment.find('=');
      if (eq == std::string::npos || eq == 0)
        throw UsageError("--topic " + assignment + ": expected ROLE=TOPIC, e.g. --topic imu=/camera/imu");
      io::set_ros_bag_topic(c.read.topics, assignment.substr(0, eq), assignment.substr(eq + 1));
    }
    c.read.depth_pair_window_s = depth_pair_window_s;
    c.camchain = camchain;
    c.imu_noise = imu_noise;
    if (!depth_range.empty()) {
      c.depth_min_m = depth_range[0];
      c.depth_max_m = depth_range[1];
      if (!(c.depth_max_m > 0)) throw UsageError("--depth-range MIN MAX: MAX must be positive");
    }
    return c;
  }
};

}  // namespace navaid::cli
