#pragma once
// Noise-free RGB-D + label rendering by ray casting: for every pixel the bearing of
// CameraModel::unproject (distortion honoured) is cast into the world.
//  - depth [m]: metric z along the optical axis (not the ray length); 0 where nothing is hit, the
//    pixel cannot be unprojected, or the depth is outside [min_depth, max_depth];
//  - labels: SemanticClass id of the hit primitive (kept even when the depth is out of range);
//    no_hit_class (default sky) where nothing is hit, unlabeled where the pixel has no bearing;
//  - intensity: procedural texture of the hit primitive evaluated at the 3D hit point (stable
//    across viewpoints, so features can be tracked) times Lambertian shading from a fixed sun plus
//    ambient; sky_intensity where nothing is hit. A plane patch with an image texture
//    (World::image_texture, e.g. an AprilTag) is box-filtered over the pixel: the mean of
//    kImageTextureSupersample^2 sub-pixel rays intersected with the patch's plane, each reading
//    the nearest texel (clamped to the picture's border).
// Sensor noise is applied separately. Rendering is single-threaded and deterministic.
#include <cstdint>
#include <memory>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/image.hpp"
#include "navaid/simulation/ray_caster.hpp"

namespace navaid::simulation {

/// Sub-pixel rays per axis on image-textured patches.
inline constexpr int kImageTextureSupersample = 4;

struct RenderOptions {
  double min_depth = 0.1;   ///< [m], depth below this is reported as 0
  double max_depth = 10.0;  ///< [m], depth above this is reported as 0
  double max_ray_distance = 500.0;  ///< rays are not traced further (labels become no_hit_class)
  bool render_depth = true;
  bool render_labels = true;
  bool render_intensity = true;
  Vec3 sun_direction_W = Vec3(0.4, 0.3, 1.0);  ///< towards the sun (normalized internally)
  double ambient = 0.35;                       ///< in [0, 1]
  SemanticClass no_hit_class = SemanticClass::kSky;
  std::uint8_t sky_intensity = 200;
};

/// Images of one frame; an image that was not requested stays empty.
struct RenderedFrame {
  ImageF32 depth;
  ImageU8 labels;
  ImageU8 intensity;
};

/// Procedural albedo texture in [0, 1] of a surface at world point p (deterministic).
double surface_texture(const Surface& surface, const Vec3& p_W);

class RgbdRenderer {
 public:
  /// Precomputes the per-pixel bearings of `camera`. Keeps references to both: they must outlive
  /// the renderer.
  RgbdRenderer(const RayCaster& caster, const CameraModel& camera);

  /// `dynamic` (may be null): a second world, e.g. moving people at this instant, rendered
  /// together with the static one (the nearer hit wins).
  RenderedFrame render(const SE3& T_W_C, const RenderOptions& options = {}, const RayCaster* dynamic = nullptr) const;
  /// Same, reusing the buffers of `out`.
  void render(const SE3& T_W_C, const RenderOptions& options, RenderedFrame& out, const RayCaster* dynamic = nullptr) const;

  /// Unit bearing in C of pixel (x, y); zero vector when the pixel cannot be unprojected.
  const Vec3& bearing(int x, int y) const { return bearings_[static_cast<std::size_t>(y) * width_ + x]; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  /// Reflectance of an image-textured plane patch over pixel i (box filter, see above).
  double image_texture(const Primitive& primitive, const ImageU8& image, const SE3& T_W_C, std::size_t i) const;

  const RayCaster* caster_;
  const CameraModel* camera_;
  int width_, height_;
  std::vector<Vec3> bearings_;
};

/// One-off conveniences (recompute the bearings, and for a World the BVH, on every call).
RenderedFrame render(const RayCaster& caster, const CameraModel& camera, const SE3& T_W_C,
                     const RenderOptions& options = {});
RenderedFrame render(const World& world, const CameraModel& camera, const SE3& T_W_C,
                     const RenderOptions& options = {}, const Tessellation& tess = {});

}  // namespace navaid::simulation
