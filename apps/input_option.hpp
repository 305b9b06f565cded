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
    cmd.add_option("input", path, "Recording folder, EuRoC/TUM RGB-D folder, NMEA capture or TUM trajectory")
        ->required();
    cmd.add_option("--format", format, "Force the input kind instead of detecting it")
        ->check(CLI::IsMember({"navaid", "euroc", "tum-rgbd", "nmea", "tum-trajectory"}));
  }

  io::InputKind kind() const {
    if (format.empty()) return io::detect_input(path);
    return *io::input_kind_from_string(format);  // CLI11 has checked the name
  }
};

/// A navaid, EuRoC or TUM RGB-D recording (the kinds with camera frames); IoError naming the path
/// and saying it is not "a recording with <what>" for any other input.
inline io::Recording read_camera_recording(const std::filesystem::path& path, const std::string& what) {
  const io::InputKind kind = io::detect_input(path);
  if (kind != io::InputKind::kNavaidRecording && kind != io::InputKind::kEuroc && kind != io::InputKind::kTumRgbd)
    throw IoError(path.string(), "is a " + std::string(io::to_string(kind)) + ", not a recording with " + what +
                                     " (navaid, EuRoC or TUM RGB-D)");
  return io::read_input(path, kind);
}

}  // namespace navaid::cli
