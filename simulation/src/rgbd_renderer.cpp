#include "navaid/simulation/rgbd_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {

std::uint32_t hash3(std::int64_t x, std::int64_t y, std::int64_t z, std::uint32_t seed) {
  // Integer mix (murmur3 finalizer over a combination of the coordinates).
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull ^ (static_cast<std::uint64_t>(seed) << 32 | seed);
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ull;
  h ^= h >> 33;
  return static_cast<std::uint32_t>(h);
}

double unit_hash(std::int64_t x, std::int64_t y, std::int64_t z, std::uint32_t seed) {
  return hash3(x, y, z, seed) * (1.0 / 4294967296.0);
}

double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

// Trilinear value noise in [0, 1).
double value_noise(const Vec3& q, std::uint32_t seed) {
  const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy), iz = static_cast<std::int64_t>(fz);
  const double u = smooth(q.x() - fx), v = smooth(q.y() - fy), w = smooth(q.z() - fz);
  double c[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c[a][b][d] = unit_hash(ix + a, iy + b, iz + d, seed);
  const double x00 = c[0][0][0] + u * (c[1][0][0] - c[0][0][0]);
  const double x10 = c[0][1][0] + u * (c[1][1][0] - c[0][1][0]);
  const double x01 = c[0][0][1] + u * (c[1][0][1] - c[0][0][1]);
  const double x11 = c[0][1][1] + u * (c[1][1][1] - c[0][1][1]);
  const double y0 = x00 + v * (x10 - x00), y1 = x01 + v * (x11 - x01);
  return y0 + w * (y1 - y0);
}

}  // namespace

double surface_texture(const Surface& surface, const Vec3& p_W) {
  // A per-seed offset keeps cell borders off the integer planes where primitives usually sit.
  const std::uint32_t seed = surface.texture_seed;
  const Vec3 offset(0.137 + 0.5 * unit_hash(1, 0, 0, seed), 0.291 + 0.5 * unit_hash(0, 1, 0, seed),
                    0.413 + 0.5 * unit_hash(0, 0, 1, seed));
  const Vec3 q = p_W / surface.texture_scale + offset;
  // Random-valued cells (sharp corners for KLT/FAST) plus finer smooth value noise.
  const double cell = unit_hash(static_cast<std::int64_t>(std::floor(q.x())), static_cast<std::int64_t>(std::floor(q.y())),
                                static_cast<std::int64_t>(std::floor(q.z())), seed ^ 0xA5A5A5A5u);
  const double fine = value_noise(2.7 * q, seed);
  const double t = 0.65 * cell + 0.35 * fine;  // [0, 1)
  return std::clamp(surface.albedo * (0.3 + 1.4 * t), 0.0, 1.0);
}

double image_reflectance(const Surface& surface, double grey) { return surface.albedo * (0.05 + 0.95 * grey / 255.0); }

RgbdRenderer::RgbdRenderer(const RayCaster& caster, const CameraModel& camera)
    : caster_(&caster), camera_(&camera), width_(camera.width()), height_(camera.height()) {
  bearings_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), Vec3::Zero());
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const auto b = camera.unproject(CameraModel::Vec2(x, y));
      if (b) bearings_[static_cast<std::size_t>(y) * width_ + x] = *b;
    }
}

double RgbdRenderer::image_texture(const Primitive& primitive, const ImageU8& img, const SE3& T_W_C,
                                   std::size_t i) const {
  const Surface& surface = primitive.surface;
  const auto& patch = std::get<PlanePatch>(primitive.shape);
  // The patch in C: its plane n . p = d, and the map from C into the patch frame.
  const SE3 T_P_C = patch.T_W_P.inverse() * T_W_C;
  const Mat3 R_P_C = T_P_C.rotation();
  const Vec3 n_P = Vec3::UnitZ();
  const Vec3 o_P = T_P_C.t;  // camera centre in P
  const int x = static_cast<int>(i % static_cast<std::size_t>(width_)), y = static_cast<int>(i / static_cast<std::size_t>(width_));
  constexpr int S = kImageTextureSupersample;
  double sum = 0.0;
  int n = 0;
  for (int sy = 0; sy < S; ++sy)
    for (int sx = 0; sx < S; ++sx) {
      const double u = x + (sx + 0.5) / S - 0.5, v = y + (sy + 0.5) / S - 0.5;
      const auto b = camera_->unproject(CameraModel::Vec2(u, v));
      if (!b) continue;
      const Vec3 d_P = R_P_C * *b;
      const double denom = n_P.dot(d_P);
      if (std::abs(denom) < 1e-12) continue;
      const double s = -n_P.dot(o_P) / denom;
      if (s <= 0.0) continue;
      const Vec3 q = o_P + s * d_P;
      const double cu = (q.x() + patch.half_x) / (2.0 * patch.half_x) * img.width;
      const double cv = (patch.half_y - q.y()) / (2.0 * patch.half_y) * img.height;
      const int col = std::clamp(static_cast<int>(std::floor(cu)), 0, img.width - 1);
      const int row = std::clamp(static_cast<int>(std::floor(cv)), 0, img.height - 1);
      sum += img.pixels[static_cast<std::size_t>(row) * img.width + col];
      ++n;
    }
  // The centre ray hit the patch, so at least some sub-rays do; fall back to it otherwise.
  if (n == 0) return image_reflectance(surface, img.pixels[0]);
  return image_reflectance(surface, sum / n);
}

RenderedFrame RgbdRenderer::render(const SE3& T_W_C, const RenderOptions& options, const RayCaster* dynamic) const {
  RenderedFrame out;
  render(T_W_C, options, out, dynamic);
  return out;
}

void RgbdRenderer::render(const SE3& T_W_C, const RenderOptions& o, RenderedFrame& out, const RayCaster* dynamic) const {
  if (!(o.min_depth >= 0.0) || !(o.max_depth >= o.min_depth) || !(o.max_ray_distance > 0.0) ||
      !(o.ambient >= 0.0 && o.ambient <= 1.0) || !(o.sun_direction_W.norm() > 0.0))
    throw Error("RenderOptions: need 0 <= min_depth <= max_depth, max_ray_distance > 0, ambient in [0, 1], "
                "nonzero sun_direction_W");
  auto reset = [&](auto& img, bool wanted, auto fill) {
    if (wanted) {
      img.width = width_;
      img.height = height_;
      img.channels = 1;
      img.pixels.assign(static_cast<std::size_t>(width_) * height_, fill);
    } else {
      img = {};
    }
  };
  reset(out.depth, o.render_depth, 0.0f);
  reset(out.labels, o.render_labels, static_cast<std::uint8_t>(SemanticClass::kUnlabeled));
  reset(out.intensity, o.render_intensity, std::uint8_t{0});

  const Mat3 R_W_C = T_W_C.rotation();
  const Vec3 origin = T_W_C.t;
  const Vec3 sun = o.sun_direction_W.normalized();
  const bool has_dynamic = dynamic != nullptr && !dynamic->mesh().triangles.empty();
  const auto sky_label = static_cast<std::uint8_t>(o.no_hit_class);
  for (std::size_t i = 0, n = bearings_.size(); i < n; ++i) {
    const Vec3& b = bearings_[i];
    if (b.z() <= 0.0) continue;  // no bearing: depth 0, unlabeled, black
    const Vec3 dir = R_W_C * b;
    auto hit = caster_->cast(origin, dir, o.max_ray_distance);
    const RayCaster* hit_caster = caster_;
    if (has_dynamic) {
      const double t_max = hit ? hit->distance : o.max_ray_distance;
      if (auto near = dynamic->cast(origin, dir, t_max)) {
        hit = near;
        hit_caster = dynamic;
      }
    }
    if (!hit) {
      if (o.render_labels) out.labels.pixels[i] = sky_label;
      if (o.render_intensity) out.intensity.pixels[i] = o.sky_intensity;
      continue;
    }
    if (o.render_depth) {
      const double z = hit->distance * b.z();
      if (z >= o.min_depth && z <= o.max_depth) out.depth.pixels[i] = static_cast<float>(z);
    }
    if (o.render_labels) out.labels.pixels[i] = static_cast<std::uint8_t>(hit->semantic);
    if (o.render_intensity) {
      const Primitive& primitive = hit_caster->world().primitive(hit->primitive);
      const Surface& surface = primitive.surface;
      const double lambert = std::abs(hit->normal.dot(sun));  // two-sided
      const double shade = o.ambient + (1.0 - o.ambient) * lambert;
      const ImageU8* image = hit_caster->world().image_texture(hit->primitive);
      const double albedo = image ? image_texture(primitive, *image, T_W_C, i) : surface_texture(surface, hit->point);
      const double v = 255.0 * albedo * shade;
      out.intensity.pixels[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
}

RenderedFrame render(const RayCaster& caster, const CameraModel& camera, const SE3& T_W_C, const RenderOptions& options) {
  return RgbdRenderer(caster, camera).render(T_W_C, options);
}

RenderedFrame render(const World& world, const CameraModel& camera, const SE3& T_W_C, const RenderOptions& options,
                     const Tessellation& tess) {
  const RayCaster caster(world, tess);
  return render(caster, camera, T_W_C, options);
}

}  // namespace navaid::simulation
