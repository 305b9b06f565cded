#include "navaid/simulation/render_cache.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"

namespace navaid::simulation {

namespace fs = std::filesystem;

double cache_depth_unit_m(double max_depth_m) {
  // The finest of 0.1, 0.2, 0.5, 1 mm whose 16-bit range holds the depth.
  for (double unit : {1e-4, 2e-4, 5e-4, 1e-3})
    if (max_depth_m <= 65535.0 * unit) return unit;
  throw ConfigError("", "render.max_depth", fmt::format("{} m is beyond the 65.5 m a 16-bit depth image holds", max_depth_m));
}

std::string stable_hash_hex(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

RenderCache::RenderCache(const fs::path& root, const std::string& key, double depth_unit_m)
    : folder_(root / stable_hash_hex(key)), depth_unit_m_(depth_unit_m) {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) throw IoError(folder_.string(), "cannot create the render cache folder: " + ec.message());
  const fs::path key_file = folder_ / "key.txt";
  if (fs::exists(key_file)) {
    std::ifstream in(key_file, std::ios::binary);
    std::stringstream stored;
    stored << in.rdbuf();
    if (stored.str() != key)
      throw IoError(key_file.string(), "render cache entry belongs to another key (hash collision); delete the folder");
  } else {
    const fs::path tmp = folder_ / "key.txt.tmp";
    std::ofstream(tmp, std::ios::binary) << key;
    fs::rename(tmp, key_file, ec);
    if (ec) throw IoError(key_file.string(), "cannot write the render cache key: " + ec.message());
  }
}

fs::path RenderCache::path(std::size_t index, const char* kind) const {
  return folder_ / fmt::format("{:06d}_{}.png", index, kind);
}

bool RenderCache::has(std::size_t index) const {
  return fs::exists(path(index, "depth")) && fs::exists(path(index, "labels")) && fs::exists(path(index, "intensity"));
}

RenderedFrame RenderCache::load(std::size_t index) const {
  RenderedFrame f;
  f.depth = io::read_depth_png(path(index, "depth").string(), depth_unit_m_);
  f.labels = io::read_label_image(path(index, "labels").string());
  f.intensity = io::read_intensity_image(path(index, "intensity").string());
  return f;
}

void RenderCache::store(std::size_t index, const RenderedFrame& frame) const {
  // Depth first; labels last: has() needs all three, and each appears atomically by rename.
  auto put = [&](const char* kind, const auto& image) {
    const fs::path final_path = path(index, kind);
    const fs::path tmp = final_path.string() + ".tmp.png";
    io::write_png(tmp.string(), image, 1);
    std::error_code ec;
    fs::rename(tmp, final_path, ec);
    if (ec) throw IoError(final_path.string(), "cannot store a cached rendering: " + ec.message());
  };
  put("depth", io::depth_to_png_units(frame.depth, depth_unit_m_, path(index, "depth").string()));
  put("intensity", frame.intensity);
  put("labels", frame.labels);
}

}  // namespace navaid::simulation
