#include "navaid/simulation/apriltag_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <fmt/format.h>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {

/// The family, created and destroyed by libapriltag.
class Family {
 public:
  explicit Family(std::string_view name) {
    if (name == "36h11") {
      f_ = tag36h11_create();
      destroy_ = tag36h11_destroy;
    } else if (name == "25h9") {
      f_ = tag25h9_create();
      destroy_ = tag25h9_destroy;
    } else if (name == "16h5") {
      f_ = tag16h5_create();
      destroy_ = tag16h5_destroy;
    } else {
      throw Error(fmt::format("unknown AprilTag family '{}'; known: 36h11, 25h9, 16h5", name));
    }
  }
  ~Family() { destroy_(f_); }
  Family(const Family&) = delete;
  Family& operator=(const Family&) = delete;
  const apriltag_family_t& operator*() const { return *f_; }

 private:
  apriltag_family_t* f_ = nullptr;
  void (*destroy_)(apriltag_family_t*) = nullptr;
};

}  // namespace

AprilTagFamilyInfo apriltag_family_info(std::string_view family) {
  const Family f(family);
  return {static_cast<int>((*f).ncodes), (*f).total_width, (*f).width_at_border};
}

ImageU8 apriltag_cells(std::string_view family, int id) {
  const Family fam(family);
  const apriltag_family_t& f = *fam;
  if (id < 0 || static_cast<std::uint32_t>(id) >= f.ncodes) {
    throw Error(fmt::format("AprilTag {} has ids 0..{}, not {}", family, f.ncodes - 1, id));
  }
  if (f.reversed_border) throw Error(fmt::format("AprilTag {}: reversed-border families are not drawn", family));
  ImageU8 cells(f.total_width, f.total_width, 1, 255);
  const int start = (f.total_width - f.width_at_border) / 2;
  for (int y = start; y < start + f.width_at_border; ++y) {
    for (int x = start; x < start + f.width_at_border; ++x) cells.at(x, y) = 0;
  }
  const std::uint64_t code = f.codes[id];
  for (std::uint32_t i = 0; i < f.nbits; ++i) {
    if ((code >> (f.nbits - 1 - i)) & 1U) cells.at(start + static_cast<int>(f.bit_x[i]), start + static_cast<int>(f.bit_y[i])) = 255;
  }
  return cells;
}

void draw_apriltag(ImageU8& image, const CameraModel& camera, const SE3& T_C_tag, double tag_size_m,
                   const ImageU8& cells, int width_at_border, int supersample, ImageF32* depth) {
  if (image.channels != 1 || cells.channels != 1 || cells.width != cells.height || width_at_border <= 0 ||
      supersample < 1 || !(tag_size_m > 0.0)) {
    throw Error("draw_apriltag: grey image and cells, a positive size and supersampling are needed");
  }
  if (depth && (depth->width != image.width || depth->height != image.height)) {
    throw Error("draw_apriltag: the depth image must have the image's size");
  }
  const double cell_m = tag_size_m / width_at_border;
  const double half_m = 0.5 * cells.width * cell_m;  // whole pattern, white ring included
  // Bounding box of the pattern in the image (corners in front of the camera only).
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
  for (const auto& c : {Vec3(-half_m, -half_m, 0), Vec3(half_m, -half_m, 0), Vec3(half_m, half_m, 0), Vec3(-half_m, half_m, 0)}) {
    const auto px = camera.project(T_C_tag * c);
    if (!px) return;  // part of the pattern behind the camera: not drawn
    u0 = std::min(u0, px->x());
    u1 = std::max(u1, px->x());
    v0 = std::min(v0, px->y());
    v1 = std::max(v1, px->y());
  }
  const Mat3 R_tag_C = T_C_tag.rotation().transpose();
  const Vec3 o_tag = T_C_tag.inverse().t;  // camera centre in the tag frame
  const int ua = std::max(0, static_cast<int>(std::floor(u0)) - 1);
  const int ub = std::min(image.width - 1, static_cast<int>(std::ceil(u1)) + 1);
  const int va = std::max(0, static_cast<int>(std::floor(v0)) - 1);
  const int vb = std::min(image.height - 1, static_cast<int>(std::ceil(v1)) + 1);
  for (int v = va; v <= vb; ++v) {
    for (int u = ua; u <= ub; ++u) {
      double sum = 0.0;
      int hits = 0;
      for (int j = 0; j < supersample; ++j) {
        for (int i = 0; i < supersample; ++i) {
          const Eigen::Vector2d px(u - 0.5 + (i + 0.5) / supersample, v - 0.5 + (j + 0.5) / supersample);
          const auto ray = camera.unproject(px);
          if (!ray) continue;
          const Vec3 d = R_tag_C * *ray;
          if (std::abs(d.z()) < 1e-12) continue;
          const double s = -o_tag.z() / d.z();
          if (s <= 0.0) continue;
          const Vec3 p = o_tag + s * d;
          const double cx = (p.x() + half_m) / cell_m;
          const double cy = (p.y() + half_m) / cell_m;
          if (cx < 0.0 || cy < 0.0 || cx >= cells.width || cy >= cells.height) continue;
          sum += cells.at(static_cast<int>(cx), static_cast<int>(cy));
          ++hits;
        }
      }
      if (hits == 0) continue;
      // Partly covered pixels blend with what is already there.
      const double n = static_cast<double>(supersample) * supersample;
      const double value = (sum + (n - hits) * image.at(u, v)) / n;
      image.at(u, v) = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
      if (depth && hits * 2 >= n) {
        const auto ray = camera.unproject(Eigen::Vector2d(u, v));
        if (ray) {
          const Vec3 d = R_tag_C * *ray;
          const double s = -o_tag.z() / d.z();
          depth->at(u, v) = static_cast<float>(s * ray->z());
        }
      }
    }
  }
}

}  // namespace navaid::simulation
