#pragma once
// The input path and optional --format shared by commands that read recordings.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/io/open_input.hpp"

namespace navaid::cli {

struct InputOption {
  std::filesystem::path path;
  std::string format;

  void add_to(CLI::App& cmd) {
    cmd.add_option("input", path, "Recording folder, EuRoC/TUM RGB-D folder, NMEA capture, TUM trajectory or ROS bag")
        ->required();
    cmd.add_option("--format", format, "Force the input kind instead of detecting it")
        ->check(CLI::IsMember({"navaid", "euroc", "tum-rgbd", "nmea", "tum-trajectory", "ros-bag"}));
  }

  io::InputKind kind() const {
    if (format.empty()) return io::detect_input(path);
    return *io::input_kind_from_string(format);  // CLI11 has checked the name
  }
};

using io::read_camera_recording;

}  // namespace navaid::cli
