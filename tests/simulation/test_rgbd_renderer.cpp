#include "pinhole_calibration.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {
namespace {

CameraCalibration radtan(int w, int h, double f) {
  CameraCalibration c = pinhole(w, h, f);
  c.distortion = DistortionModel::kRadialTangential;
  c.distortion_coeffs = {-0.25, 0.07, 0.001, -0.0005};
  return c;
}

// Camera at `eye` looking at `target`, image x right, y down, with W z up.
SE3 look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  Vec3 x = z.cross(Vec3::UnitZ());
  if (x.norm() < 1e-9) x = Vec3::UnitX();
  x.normalize();
  const Vec3 y = z.cross(x);
  Mat3 R;
  R << x, y, z;
  return SE3(R, eye);
}

// Floor 10 x 10 at z = 0, a box and a cylinder at known places.
const Box kBox{SE3(quat_from_rpy(0, 0, 0.3), Vec3(1.0, 1.0, 0.5)), Vec3(0.5, 0.4, 0.5)};
const VerticalCylinder kCylinder{Vec3(-1.0, -1.0, 0.0), 0.3, 1.2};

World scene() {
  World w;
  w.add(PlanePatch{SE3(), 5.0, 5.0}, Surface{SemanticClass::kFloor, 11, 0.15, 0.8});
  w.add(kBox, Surface{SemanticClass::kTable, 12, 0.1, 0.7});
  w.add(kCylinder, Surface{SemanticClass::kPole, 13, 0.05, 0.6});
  return w;
}

Vec3 back_project(const RgbdRenderer& r, const RenderedFrame& f, const SE3& T_W_C, int x, int y) {
  const Vec3& b = r.bearing(x, y);
  return T_W_C * Vec3(b * (f.depth.at(x, y) / b.z()));
}

TEST(RgbdRenderer, DepthBackProjectsOntoFloorAndBoxFaces) {
  const RayCaster rc(scene());
  const auto cam = make_camera_model(radtan(160, 120, 110.0));
  const RgbdRenderer r(rc, *cam);
  const SE3 T_W_C = look_at(Vec3(-3.0, -2.5, 2.2), Vec3(0.3, 0.2, 0.3));
  RenderOptions opt;
  opt.max_depth = 20.0;
  const RenderedFrame f = r.render(T_W_C, opt);
  const SE3 T_O_W = kBox.T_W_O.inverse();
  int floor_px = 0, box_px = 0;
  for (int y = 0; y < f.depth.height; ++y)
    for (int x = 0; x < f.depth.width; ++x) {
      const float d = f.depth.at(x, y);
      const auto label = static_cast<SemanticClass>(f.labels.at(x, y));
      if (d == 0.0f) {
        EXPECT_TRUE(label == SemanticClass::kSky) << x << "," << y;
        continue;
      }
      // Depth is stored as float: its rounding (2^-24 relative) bounds the back-projection error.
      const Vec3 p = back_project(r, f, T_W_C, x, y);
      const double tol = 1e-6 * d;
      if (label == SemanticClass::kFloor) {
        ++floor_px;
        EXPECT_NEAR(p.z(), 0.0, tol) << x << "," << y;
      } else if (label == SemanticClass::kTable) {
        ++box_px;
        const Vec3 p_O = T_O_W * p;
        EXPECT_NEAR((p_O.cwiseAbs() - kBox.half_extents).maxCoeff(), 0.0, tol) << x << "," << y;
      }
    }
  EXPECT_GT(floor_px, 3000);
  EXPECT_GT(box_px, 200);
}

TEST(RgbdRenderer, DepthIsOpticalAxisZAndDoubleRayExact) {
  // Looking straight down on the floor from 2 m: every valid depth is exactly 2 (z, not range).
  World w;
  w.add(PlanePatch{SE3(), 50.0, 50.0}, Surface{SemanticClass::kSidewalk, 1, 0.2, 0.7});
  const RayCaster rc(w);
  const auto cam = make_camera_model(pinhole(64, 48, 40.0));
  const RgbdRenderer r(rc, *cam);
  const SE3 T_W_C = look_at(Vec3(0.3, -0.2, 2.0), Vec3(0.3, -0.2, 0.0));
  const RenderedFrame f = r.render(T_W_C);
  for (float d : f.depth.pixels) EXPECT_NEAR(d, 2.0, 2.0 * 1e-7);
}

TEST(RgbdRenderer, LabelsMatchKnownLayout) {
  const RayCaster rc(scene());
  const auto cam = make_camera_model(pinhole(160, 120, 80.0));
  const RgbdRenderer r(rc, *cam);
  // Straight down from 4 m above the origin.
  const SE3 T_W_C = look_at(Vec3(0, 0, 4.0), Vec3(0, 0, 0)) ;
  const RenderedFrame f = r.render(T_W_C);
  const SE3 T_C_W = T_W_C.inverse();
  auto label_at = [&](const Vec3& p_W) {
    const auto px = cam->project(T_C_W * p_W);
    EXPECT_TRUE(px && cam->in_image(*px));
    return static_cast<SemanticClass>(f.labels.at(static_cast<int>(std::lround(px->x())), static_cast<int>(std::lround(px->y()))));
  };
  EXPECT_EQ(label_at(kBox.T_W_O * Vec3(0, 0, 0.5)), SemanticClass::kTable);
  EXPECT_EQ(label_at(kCylinder.base_center + Vec3(0, 0, 1.2)), SemanticClass::kPole);
  EXPECT_EQ(label_at(Vec3(1.0, -1.0, 0.0)), SemanticClass::kFloor);
  EXPECT_EQ(label_at(Vec3(-1.5, 1.2, 0.0)), SemanticClass::kFloor);
  // Box top at z = 1: depth 3; cylinder top: 2.8; floor: 4.
  auto depth_at = [&](const Vec3& p_W) {
    const auto px = cam->project(T_C_W * p_W);
    return f.depth.at(static_cast<int>(std::lround(px->x())), static_cast<int>(std::lround(px->y())));
  };
  EXPECT_NEAR(depth_at(kBox.T_W_O * Vec3(0, 0, 0.5)), 3.0, 1e-6);
  EXPECT_NEAR(depth_at(kCylinder.base_center + Vec3(0, 0, 1.2)), 2.8, 1e-6);
  EXPECT_NEAR(depth_at(Vec3(1.0, -1.0, 0.0)), 4.0, 1e-6);
  // Every pixel is floor, table or pole; the pixels seeing the tops (depth 3 resp. 2.8) cover
  // their areas (sides are visible too in perspective, at other depths).
  int table = 0, pole = 0;
  for (std::size_t i = 0; i < f.labels.pixels.size(); ++i) {
    const auto c = static_cast<SemanticClass>(f.labels.pixels[i]);
    const float d = f.depth.pixels[i];
    EXPECT_TRUE(c == SemanticClass::kFloor || c == SemanticClass::kTable || c == SemanticClass::kPole);
    table += c == SemanticClass::kTable && std::abs(d - 3.0f) < 1e-4f;
    pole += c == SemanticClass::kPole && std::abs(d - 2.8f) < 1e-4f;
  }
  const double px_per_m_box = 80.0 / 3.0, px_per_m_cyl = 80.0 / 2.8;
  EXPECT_NEAR(table, 1.0 * 0.8 * px_per_m_box * px_per_m_box, 0.15 * 1.0 * 0.8 * px_per_m_box * px_per_m_box);
  EXPECT_NEAR(pole, 3.14159 * 0.09 * px_per_m_cyl * px_per_m_cyl, 0.25 * 3.14159 * 0.09 * px_per_m_cyl * px_per_m_cyl);

  // Looking at the horizon: sky above, depth 0 there.
  const RenderedFrame g = r.render(look_at(Vec3(-4, 0, 1.0), Vec3(10, 0, 1.0)));
  for (int x = 0; x < 160; ++x) {
    EXPECT_EQ(static_cast<SemanticClass>(g.labels.at(x, 5)), SemanticClass::kSky);
    EXPECT_EQ(g.depth.at(x, 5), 0.0f);
    EXPECT_EQ(static_cast<SemanticClass>(g.labels.at(x, 115)), SemanticClass::kFloor);
  }
}

TEST(RgbdRenderer, RangeLimitsGiveZeroDepthButKeepLabels) {
  const RayCaster rc(scene());
  const auto cam = make_camera_model(pinhole(80, 60, 50.0));
  const RgbdRenderer r(rc, *cam);
  const SE3 T_W_C = look_at(Vec3(-4.5, 0.0, 1.5), Vec3(2.0, 0.0, 0.0));
  RenderOptions opt;
  opt.max_depth = 100.0;
  opt.min_depth = 0.0;
  const RenderedFrame full = r.render(T_W_C, opt);
  opt.min_depth = 2.0;
  opt.max_depth = 4.0;
  const RenderedFrame clipped = r.render(T_W_C, opt);
  int zeroed_near = 0, zeroed_far = 0, kept = 0;
  for (std::size_t i = 0; i < full.depth.pixels.size(); ++i) {
    const float d = full.depth.pixels[i], c = clipped.depth.pixels[i];
    EXPECT_EQ(full.labels.pixels[i], clipped.labels.pixels[i]);
    if (d == 0.0f) {
      EXPECT_EQ(c, 0.0f);
    } else if (d < 2.0f) {
      EXPECT_EQ(c, 0.0f);
      ++zeroed_near;
    } else if (d > 4.0f) {
      EXPECT_EQ(c, 0.0f);
      ++zeroed_far;
    } else {
      EXPECT_EQ(c, d);
      ++kept;
    }
  }
  EXPECT_GT(zeroed_near, 10);
  EXPECT_GT(zeroed_far, 10);
  EXPECT_GT(kept, 10);
  opt.min_depth = 5.0;
  EXPECT_THROW(r.render(T_W_C, opt), Error);
}

// Shi-Tomasi response (smaller eigenvalue of the 5x5 structure tensor of central differences).
int count_corners(const ImageU8& img, double threshold) {
  const int w = img.width, h = img.height;
  std::vector<double> gx(static_cast<std::size_t>(w * h), 0.0), gy(gx.size(), 0.0), score(gx.size(), 0.0);
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      gx[static_cast<std::size_t>(y * w + x)] = 0.5 * (img.at(x + 1, y) - img.at(x - 1, y));
      gy[static_cast<std::size_t>(y * w + x)] = 0.5 * (img.at(x, y + 1) - img.at(x, y - 1));
    }
  for (int y = 3; y < h - 3; ++y)
    for (int x = 3; x < w - 3; ++x) {
      double a = 0, b = 0, c = 0;
      for (int v = -2; v <= 2; ++v)
        for (int u = -2; u <= 2; ++u) {
          const auto k = static_cast<std::size_t>((y + v) * w + x + u);
          a += gx[k] * gx[k];
          b += gx[k] * gy[k];
          c += gy[k] * gy[k];
        }
      score[static_cast<std::size_t>(y * w + x)] = 0.5 * (a + c) - std::sqrt(0.25 * (a - c) * (a - c) + b * b);
    }
  int n = 0;
  for (int y = 4; y < h - 4; ++y)
    for (int x = 4; x < w - 4; ++x) {
      const double s = score[static_cast<std::size_t>(y * w + x)];
      if (s < threshold) continue;
      bool is_max = true;
      for (int v = -3; v <= 3 && is_max; ++v)
        for (int u = -3; u <= 3; ++u)
          if ((u || v) && score[static_cast<std::size_t>((y + v) * w + x + u)] > s) {
            is_max = false;
            break;
          }
      n += is_max;
    }
  return n;
}

TEST(RgbdRenderer, IntensityIsTexturedAndDeterministic) {
  const RayCaster rc(scene());
  const auto cam = make_camera_model(pinhole(160, 120, 110.0));
  const RgbdRenderer r(rc, *cam);
  const SE3 T_W_C = look_at(Vec3(-3.0, -2.5, 2.2), Vec3(0.3, 0.2, 0.3));
  const RenderedFrame a = r.render(T_W_C);
  const RenderedFrame b = render(rc, *cam, T_W_C);
  EXPECT_EQ(a.intensity, b.intensity);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.labels, b.labels);
  const RenderedFrame c = render(scene(), *cam, T_W_C);  // fresh BVH: same images
  EXPECT_EQ(a.intensity, c.intensity);
  EXPECT_EQ(a.depth, c.depth);

  double mean = 0, sq = 0;
  for (auto v : a.intensity.pixels) {
    mean += v;
    sq += static_cast<double>(v) * v;
  }
  mean /= static_cast<double>(a.intensity.pixels.size());
  const double var = sq / static_cast<double>(a.intensity.pixels.size()) - mean * mean;
  EXPECT_GT(var, 200.0);  // std > 14 grey levels
  const int corners = count_corners(a.intensity, 25.0 * 100.0);  // min eigenvalue ~ (10 grey/px)^2 * 25
  EXPECT_GT(corners, 50) << corners;

  // The texture is attached to the surface: the same world point keeps its albedo.
  const Surface s{SemanticClass::kFloor, 11, 0.15, 0.8};
  EXPECT_EQ(surface_texture(s, Vec3(0.3, 0.4, 0.0)), surface_texture(s, Vec3(0.3, 0.4, 0.0)));
  Surface other = s;
  other.texture_seed = 99;
  int differ = 0;
  for (int i = 0; i < 50; ++i)
    differ += surface_texture(s, Vec3(0.1 * i, 0.05 * i, 0)) != surface_texture(other, Vec3(0.1 * i, 0.05 * i, 0));
  EXPECT_GT(differ, 40);

  // Options: only labels requested.
  RenderOptions opt;
  opt.render_depth = false;
  opt.render_intensity = false;
  const RenderedFrame l = r.render(T_W_C, opt);
  EXPECT_TRUE(l.depth.empty());
  EXPECT_TRUE(l.intensity.empty());
  EXPECT_EQ(l.labels, a.labels);
}

}  // namespace
}  // namespace navaid::simulation
