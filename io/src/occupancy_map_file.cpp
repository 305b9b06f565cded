#include "navaid/io/occupancy_map_file.hpp"

#include "calibration_yaml.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"

namespace navaid::io {

double OccupancyMapFile::occupancy_probability(int x, int y) const {
  const double v = image.at(x, y);
  return negate ? v / 255.0 : (255.0 - v) / 255.0;
}

OccupancyCell OccupancyMapFile::cell(int x, int y) const {
  const double p = occupancy_probability(x, y);
  if (p > occupied_thresh) return OccupancyCell::kOccupied;
  if (p < free_thresh) return OccupancyCell::kFree;
  return OccupancyCell::kUnknown;
}

OccupancyMapFile read_occupancy_map(const std::filesystem::path& yaml_path) {
  const detail::YamlFile file(yaml_path);
  if (!file.root.IsMap()) throw IoError(file.path, "a map_server map must be a YAML mapping");
  OccupancyMapFile m;
  m.yaml_path = yaml_path;
  const std::string image = detail::as_string(file, detail::require(file, file.root, "", "image"), "image");
  m.image_path = std::filesystem::path(image).is_absolute() ? std::filesystem::path(image)
                                                            : yaml_path.parent_path() / image;
  m.resolution_m = detail::as_double(file, detail::require(file, file.root, "", "resolution"), "resolution");
  if (!(m.resolution_m > 0.0)) throw ConfigError(file.path, "resolution", "must be > 0");
  const std::vector<double> origin =
      detail::as_doubles(file, detail::require(file, file.root, "", "origin"), "origin", 3);
  m.origin_x_m = origin[0];
  m.origin_y_m = origin[1];
  m.origin_yaw_rad = origin[2];
  if (detail::has_key(file.root, "negate")) {
    m.negate = detail::as_int(file, file.root["negate"], "negate") != 0;
  }
  m.occupied_thresh = detail::as_double(file, detail::require(file, file.root, "", "occupied_thresh"), "occupied_thresh");
  m.free_thresh = detail::as_double(file, detail::require(file, file.root, "", "free_thresh"), "free_thresh");
  if (m.occupied_thresh < 0.0 || m.occupied_thresh > 1.0)
    throw ConfigError(file.path, "occupied_thresh", "must lie in [0, 1]");
  if (m.free_thresh < 0.0 || m.free_thresh > 1.0) throw ConfigError(file.path, "free_thresh", "must lie in [0, 1]");
  if (m.free_thresh >= m.occupied_thresh)
    throw ConfigError(file.path, "free_thresh", "must be smaller than occupied_thresh");
  if (detail::has_key(file.root, "mode")) {
    m.mode = detail::as_string(file, file.root["mode"], "mode");
    if (m.mode != "trinary" && m.mode != "scale")
      throw ConfigError(file.path, "mode", "'" + m.mode + "' is not supported (trinary or scale)");
  }
  const ImageU8 pixels = read_intensity_image(m.image_path.string());
  if (pixels.channels == 1) {
    m.image = pixels;
  } else {
    m.image = ImageU8(pixels.width, pixels.height, 1);
    for (int y = 0; y < pixels.height; ++y)
      for (int x = 0; x < pixels.width; ++x) {
        int sum = 0;
        for (int c = 0; c < pixels.channels; ++c) sum += pixels.at(x, y, c);
        m.image.at(x, y) = static_cast<std::uint8_t>(sum / pixels.channels);
      }
  }
  if (m.image.width == 0 || m.image.height == 0) throw IoError(m.image_path.string(), "map image is empty");
  return m;
}

}  // namespace navaid::io
