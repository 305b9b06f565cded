#pragma once
// 2D occupancy maps in the ROS map_server format: a YAML file (image, resolution, origin
// [x, y, yaw], negate, occupied_thresh, free_thresh, optional mode) beside a PGM/PNG image whose
// row 0 is the top (largest y) of the map. navaid reads them for `navaid plan` (real office maps)
// and writes them for scenario maps (simulation/occupancy_export.hpp).
#include <cstdint>
#include <filesystem>
#include <string>

#include "navaid/core/image.hpp"

namespace navaid::io {

enum class OccupancyCell : std::uint8_t { kFree, kOccupied, kUnknown };

struct OccupancyMapFile {
  std::filesystem::path yaml_path;
  std::filesystem::path image_path;
  ImageU8 image;               ///< grey values as stored (colour images averaged per pixel)
  double resolution_m = 0.05;  ///< > 0
  double origin_x_m = 0.0;     ///< lower-left pixel's corner in the map frame
  double origin_y_m = 0.0;
  double origin_yaw_rad = 0.0;
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  std::string mode = "trinary";  ///< "trinary" or "scale"; "raw" is rejected

  /// map_server's rule: p = (255 - v) / 255 (v / 255 when negated); occupied when p > occupied,
  /// free when p < free, unknown between.
  double occupancy_probability(int x, int y) const;
  OccupancyCell cell(int x, int y) const;
};

/// Reads the YAML and its image (relative paths are relative to the YAML's folder). Throws
/// IoError for missing / unreadable files and ConfigError naming the key for missing or
/// out-of-range values (resolution <= 0, thresholds outside [0, 1] or free >= occupied, an
/// unknown mode).
OccupancyMapFile read_occupancy_map(const std::filesystem::path& yaml_path);

}  // namespace navaid::io
