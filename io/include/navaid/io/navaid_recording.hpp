#pragma once
// The navaid recording format: a folder holding recording.yaml, calibration.yaml, one CSV per
// stream (imu, gps, mag, groundtruth, frames, features, landmarks) and the frame images in rgb/,
// depth/, labels/ and confidence/. The format is a public contract, specified in docs/recording-format.md.
//
// Writing then reading gives back the same values (numbers are printed in shortest round-trip
// form), and writing what was read gives byte-identical files.
#include <cstddef>
#include <filesystem>
#include <functional>

#include "navaid/io/recording.hpp"

namespace navaid::io {

constexpr const char* kNavaidFormatName = "navaid-recording";
/// The version the writer writes; readers accept kNavaidOldestVersion to kNavaidFormatVersion.
constexpr int kNavaidFormatVersion = 2;
constexpr int kNavaidOldestVersion = 1;
/// Depth PNGs of the navaid format hold millimetres.
constexpr double kNavaidDepthScaleM = 0.001;

struct NavaidWriteOptions {
  /// Write into a folder that already holds files: the recording's own files and folders are
  /// replaced, anything else is left alone. Refused when frames read their images from there.
  bool overwrite = false;
  /// zlib level (0-9) of the PNGs written.
  int png_compression = 3;
  /// Per-class probabilities are not part of the format (label_confidence is); frames carrying
  /// them are an error unless this is set, in which case they are left out.
  bool drop_class_probabilities = false;
  /// The frame images already lie in the destination folder under the names this writer gives
  /// them (rgb/<camera>_<t_ns>.png, ...), written there by the producer (the simulator writes
  /// each frame as it makes it instead of holding a whole recording in memory). They are checked
  /// to exist and kept as they are, not re-encoded; an image path elsewhere is an error.
  bool images_in_place = false;
  /// Called after each frame's images are written (done, total), for progress display.
  std::function<void(std::size_t, std::size_t)> on_frame_written;
};

/// True when `folder` holds a recording.yaml (cheap format detection, no validation).
bool is_navaid_recording(const std::filesystem::path& folder);

/// Reads and validates a navaid recording of any supported version. Frame image paths are set
/// (joined to `folder`) and checked to exist; pixels are not loaded. Throws IoError naming file and line for bad CSV data
/// and missing images, ConfigError naming file and key for bad YAML values.
Recording read_navaid_recording(const std::filesystem::path& folder);

/// Writes `recording` as a navaid recording into `folder` (created when missing). Frame images are
/// read from their source paths (or taken from the frame's loaded pixels when the path is empty)
/// and re-encoded as PNG: intensity as 8-bit grey/RGB, depth as 16-bit millimetres, labels as
/// 8-bit class ids. Throws IoError when data cannot be represented (out-of-order samples,
/// non-finite values, depth beyond 65.535 m) and ConfigError for unusable calibration values.
void write_navaid_recording(const Recording& recording, const std::filesystem::path& folder,
                            const NavaidWriteOptions& options = {});

}  // namespace navaid::io
