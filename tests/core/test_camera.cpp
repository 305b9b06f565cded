#include "navaid/core/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid {
namespace {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;


// EuRoC MAV cam0 (Kalibr radtan).
CameraCalibration euroc_radtan() {
  CameraCalibration c;
  c.name = "euroc_cam0";
  c.width = 752;
  c.height = 480;
  c.fx = 458.654;
  c.fy = 457.296;
  c.cx = 367.215;
  c.cy = 248.375;
  c.distortion = DistortionModel::kRadialTangential;
  c.distortion_coeffs = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  return c;
}

// Same with an OpenCV-style fifth coefficient k3; the negative k3 makes the radial map fold far
// outside the image.
CameraCalibration radtan_k3() {
  CameraCalibration c = euroc_radtan();
  c.name = "radtan_k3";
  c.distortion_coeffs.push_back(-0.004);
  return c;
}

// A wide-angle fisheye (T265-like intrinsics) whose image corners lie beyond 90 degrees.
CameraCalibration fisheye() {
  CameraCalibration c;
  c.name = "fisheye";
  c.width = 848;
  c.height = 800;
  c.fx = 286.1;
  c.fy = 286.3;
  c.cx = 421.6;
  c.cy = 399.5;
  c.distortion = DistortionModel::kEquidistant;
  c.distortion_coeffs = {-0.0140, 0.0209, -0.0164, 0.0047};
  return c;
}

CameraCalibration pinhole() {
  CameraCalibration c;
  c.name = "rgbd";
  c.width = 640;
  c.height = 480;
  c.fx = 525.0;
  c.fy = 524.5;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

std::vector<CameraCalibration> all_models() { return {pinhole(), euroc_radtan(), radtan_k3(), fisheye()}; }

// Pixels on a grid covering the whole image, borders and corners included.
std::vector<Vec2> pixel_grid(const CameraModel& cam, int steps = 24) {
  std::vector<Vec2> out;
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; j <= steps; ++j)
      out.emplace_back((cam.width() - 1.0) * i / steps, (cam.height() - 1.0) * j / steps);
  return out;
}

// Pixels that the model must be able to unproject: for the fisheye only those within 85 degrees
// (its image corners see past 90 and have no z = 1 representation).
bool must_unproject(const CameraModel& cam, const Vec2& pixel) {
  if (cam.distortion() != DistortionModel::kEquidistant) return true;
  return cam.distorted_from_pixel(pixel).norm() < 85.0 * M_PI / 180.0;
}

TEST(Camera, FactoryBuildsTheRequestedModel) {
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    ASSERT_TRUE(cam);
    EXPECT_EQ(cam->distortion(), calib.distortion);
    EXPECT_EQ(cam->name(), calib.name);
    EXPECT_EQ(cam->width(), calib.width);
    EXPECT_EQ(cam->height(), calib.height);
    EXPECT_EQ(cam->fx(), calib.fx);
    EXPECT_EQ(cam->cy(), calib.cy);
    EXPECT_EQ(cam->K()(0, 2), calib.cx);
    EXPECT_EQ(cam->K()(1, 1), calib.fy);
  }
}

TEST(Camera, UnprojectProjectRoundTripAcrossTheImage) {
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    int unprojected = 0;
    for (const Vec2& px : pixel_grid(*cam)) {
      const auto bearing = cam->unproject(px);
      if (!bearing) {
        EXPECT_FALSE(must_unproject(*cam, px)) << calib.name << " " << px.transpose();
        continue;
      }
      ++unprojected;
      EXPECT_NEAR(bearing->norm(), 1.0, 1e-14);
      EXPECT_GT(bearing->z(), 0.0);
      for (double depth : {0.3, 4.0, 50.0}) {
        const auto back = cam->project(depth * *bearing);
        ASSERT_TRUE(back) << calib.name << " " << px.transpose();
        EXPECT_LT((*back - px).norm(), 1e-8) << calib.name << " " << px.transpose();
      }
    }
    EXPECT_GT(unprojected, 500) << calib.name;
  }
}

TEST(Camera, ProjectUnprojectRoundTripForPointsInView) {
  std::mt19937 rng(1);
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    std::uniform_real_distribution<double> u(0.0, cam->width() - 1.0), v(0.0, cam->height() - 1.0);
    std::uniform_real_distribution<double> depth(0.2, 30.0);
    int checked = 0;
    for (int attempt = 0; attempt < 10000 && checked < 200; ++attempt) {
      // Points are drawn through the pinhole projection, then those the model sees are kept. Drawn
      // v, u, depth: GCC's order for the arguments and Eigen's operator* operands, the order of
      // record (random_draws.hpp).
      const double y = (v(rng) - calib.cy) / calib.fy;
      const double x = (u(rng) - calib.cx) / calib.fx;
      const Vec3 p = depth(rng) * Vec3(x, y, 1.0);
      const auto px = cam->project(p);
      ASSERT_TRUE(px) << calib.name;
      if (!cam->in_image(*px)) continue;
      const auto bearing = cam->unproject(*px);
      ASSERT_TRUE(bearing) << calib.name;
      EXPECT_LT((*bearing - p.normalized()).norm(), 1e-11) << calib.name << " " << p.transpose();
      ++checked;
    }
    EXPECT_EQ(checked, 200) << calib.name;
  }
}

TEST(Camera, UndistortInvertsDistortToTolerance) {
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    for (const Vec2& px : pixel_grid(*cam)) {
      const Vec2 d = cam->distorted_from_pixel(px);
      const auto n = cam->undistort(d);
      if (!n) continue;
      EXPECT_LE((cam->distort(*n) - d).norm(), CameraModel::kUndistortTolerance * std::max(1.0, d.norm()));
    }
  }
}

Mat23 numeric_project_jacobian(const CameraModel& cam, const Vec3& p) {
  Mat23 J;
  const double h = 1e-6 * p.norm();
  for (int i = 0; i < 3; ++i) {
    const Vec3 d = Vec3::Unit(i) * h;
    J.col(i) = (*cam.project(p + d) - *cam.project(p - d)) / (2 * h);
  }
  return J;
}

Mat2 numeric_distort_jacobian(const CameraModel& cam, const Vec2& n) {
  Mat2 J;
  const double h = 1e-7;
  for (int i = 0; i < 2; ++i) {
    const Vec2 d = Vec2::Unit(i) * h;
    J.col(i) = (cam.distort(n + d) - cam.distort(n - d)) / (2 * h);
  }
  return J;
}

TEST(Camera, ProjectJacobianMatchesNumeric) {
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    for (const Vec2& px : pixel_grid(*cam, 6)) {
      const auto bearing = cam->unproject(px);
      if (!bearing) continue;
      const Vec3 p = 2.5 * *bearing;
      Mat23 J;
      const auto with_jacobian = cam->project(p, &J);
      ASSERT_TRUE(with_jacobian);
      EXPECT_TRUE(*with_jacobian == *cam->project(p)) << "the Jacobian must not change the value";
      const Mat23 numeric = numeric_project_jacobian(*cam, p);
      EXPECT_LT((J - numeric).norm(), 1e-6 * numeric.norm()) << calib.name << " at " << px.transpose() << "\n"
                                                              << J << "\nvs\n"
                                                              << numeric;
    }
  }
}

TEST(Camera, DistortJacobianMatchesNumeric) {
  // Includes the exact centre and points around 0.1, where the equidistant model switches from
  // a series to the closed form.
  const std::vector<Vec2> points = {Vec2(0, 0),         Vec2(1e-9, -2e-9),  Vec2(0.05, 0.02), Vec2(0.0999, 0.0),
                                    Vec2(0.1001, 0.0),  Vec2(-0.3, 0.25),   Vec2(0.7, -0.45), Vec2(-0.9, -0.6),
                                    Vec2(1.4, 0.9),     Vec2(-2.5, 1.5)};
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    for (const Vec2& n : points) {
      if (!(n.norm() < cam->max_radius())) continue;
      Mat2 J;
      const Vec2 d = cam->distort(n, &J);
      EXPECT_TRUE(d == cam->distort(n)) << "the Jacobian must not change the value";
      const Mat2 numeric = numeric_distort_jacobian(*cam, n);
      EXPECT_LT((J - numeric).norm(), 1e-7 * std::max(1.0, numeric.norm()))
          << calib.name << " at " << n.transpose() << "\n"
          << J << "\nvs\n"
          << numeric;
    }
  }
}

TEST(Camera, RadTanKnownAnswers) {
  // Hand computation for p_C = (0.3, -0.2, 1): r^2 = 0.13,
  //   radial = 1 + k1 0.13 + k2 0.13^2 = 0.964406853978,
  //   x_d = 0.3 radial + 2 p1 (0.3)(-0.2) + p2 (0.13 + 2 0.09) = 0.289304286,
  //   u = fx x_d + cx = 499.905569.
  // All values agree with OpenCV 4.6 cv::projectPoints (printed to 1e-10 px).
  struct Case {
    Vec3 p;
    Vec2 radtan4, radtan5;
  };
  const std::vector<Case> cases = {
      {Vec3(0.3, -0.2, 1.0), Vec2(499.9055685393, 160.1887446901), Vec2(499.9043593439, 160.1895484336)},
      {Vec3(-0.55, 0.4, 1.2), Vec2(174.5086058218, 388.1404586034), Vec2(174.5364653883, 388.1202570915)},
      {Vec3(0.9, 0.6, 2.0), Vec2(557.8354611385, 375.1033665875), Vec2(557.8148009014, 375.0896338771)},
      {Vec3(-1.0, -0.7, 1.5), Vec2(108.9826900429, 68.2024820924), Vec2(109.3378836729, 68.4503814640)},
  };
  const auto cam4 = make_camera_model(euroc_radtan());
  const auto cam5 = make_camera_model(radtan_k3());
  for (const auto& c : cases) {
    EXPECT_LT((*cam4->project(c.p) - c.radtan4).norm(), 1e-8) << c.p.transpose();
    EXPECT_LT((*cam5->project(c.p) - c.radtan5).norm(), 1e-8) << c.p.transpose();
  }
  // Distortion of the centre is nothing; tangential terms move the point even on an axis.
  EXPECT_TRUE(cam4->distort(Vec2::Zero()).isZero(0.0));
  const double p2 = 1.76187114e-05, k1 = -0.28340811, k2 = 0.07395907;
  EXPECT_NEAR(cam4->distort(Vec2(0.5, 0)).x(), 0.5 * (1 + k1 * 0.25 + k2 * 0.0625) + p2 * 0.75, 1e-15);
}

TEST(Camera, EquidistantMatchesItsDefinition) {
  const CameraCalibration calib = fisheye();
  const auto cam = make_camera_model(calib);
  const auto& k = calib.distortion_coeffs;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    // Directions up to 89 degrees off axis.
    const double angle = 89.0 * M_PI / 180.0 * std::abs(u(rng));
    const double azimuth = M_PI * u(rng);
    const Vec3 p = (2.0 + u(rng)) * Vec3(std::sin(angle) * std::cos(azimuth), std::sin(angle) * std::sin(azimuth),
                                         std::cos(angle));
    const double rho = std::hypot(p.x(), p.y());
    const double theta = std::atan2(rho, p.z());
    const double t2 = theta * theta;
    const double theta_d = theta * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 + k[3] * t2 * t2 * t2 * t2);
    const Vec2 expected(calib.fx * theta_d * p.x() / rho + calib.cx, calib.fy * theta_d * p.y() / rho + calib.cy);
    const auto px = cam->project(p);
    ASSERT_TRUE(px);
    EXPECT_LT((*px - expected).norm(), 1e-9) << p.transpose();
  }
  // Reference values from OpenCV 4.6 cv::fisheye::projectPoints, out to 77 degrees off axis.
  const std::vector<std::pair<Vec3, Vec2>> opencv = {
      {Vec3(0.3, -0.2, 1.0), Vec2(503.8606755257, 344.6212130887)},
      {Vec3(-1.5, 1.1, 1.0), Vec2(174.2973133222, 580.9820811265)},
      {Vec3(2.0, 1.0, 0.5), Vec2(766.0588161674, 571.8498061320)},
      {Vec3(-0.4, -3.0, 0.8), Vec2(372.2018639234, 28.7549888484)},
  };
  for (const auto& [p, expected] : opencv) EXPECT_LT((*cam->project(p) - expected).norm(), 1e-8) << p.transpose();
  // The optical axis maps to the principal point.
  EXPECT_TRUE(cam->project(Vec3(0, 0, 3))->isApprox(Vec2(calib.cx, calib.cy), 1e-15));
}

TEST(Camera, PinholeIsTheIntrinsicsOnly) {
  const auto cam = make_camera_model(pinhole());
  const Vec3 p(0.4, -0.3, 2.0);
  const Vec2 px = *cam->project(p);
  EXPECT_NEAR(px.x(), 525.0 * 0.2 + 319.5, 1e-12);
  EXPECT_NEAR(px.y(), 524.5 * -0.15 + 239.5, 1e-12);
  EXPECT_TRUE(std::isinf(cam->max_radius()));
  EXPECT_TRUE(cam->unproject(px)->isApprox(p.normalized(), 1e-14));
}

TEST(Camera, PointsBehindTheCameraDoNotProject) {
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    Mat23 J = Mat23::Constant(7.0);
    EXPECT_FALSE(cam->project(Vec3(0.1, 0.1, 0.0), &J));
    EXPECT_FALSE(cam->project(Vec3(0.1, 0.1, -1.0)));
    EXPECT_FALSE(cam->project(Vec3(0.0, 0.0, 1e-12)));
    EXPECT_FALSE(cam->project(Vec3(0.0, 0.0, std::numeric_limits<double>::quiet_NaN())));
    EXPECT_FALSE(cam->project(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 1.0)));
    EXPECT_TRUE((J.array() == 7.0).all()) << "J must be untouched on failure";
  }
}

TEST(Camera, FoldOfTheRadialPolynomialIsRefused) {
  // Pure barrel k1 = -0.5: d/dr r(1 + k1 r^2) = 1 - 1.5 r^2 vanishes at r = sqrt(2/3).
  CameraCalibration c = euroc_radtan();
  c.distortion_coeffs = {-0.5, 0.0, 0.0, 0.0};
  const auto cam = make_camera_model(c);
  EXPECT_NEAR(cam->max_radius(), std::sqrt(2.0 / 3.0), 1e-12);
  // A point beyond the fold would land back inside the image: refuse it.
  EXPECT_TRUE(cam->project(Vec3(0.8, 0.0, 1.0)));
  EXPECT_FALSE(cam->project(Vec3(1.2, 0.0, 1.0)));
  // The largest distorted radius is r(1 - r^2/2) at the fold; beyond it undistort has no answer.
  const double max_d = std::sqrt(2.0 / 3.0) * (1.0 - 1.0 / 3.0);
  EXPECT_TRUE(cam->undistort(Vec2(0.98 * max_d, 0.0)));
  EXPECT_FALSE(cam->undistort(Vec2(1.02 * max_d, 0.0)));
  // A distorted point with two preimages resolves to the one inside the fold.
  const Vec2 ghost = cam->distort(Vec2(1.0, 0.0));  // r = 1 beyond the fold maps to 0.5
  const auto n = cam->undistort(ghost);
  ASSERT_TRUE(n);
  EXPECT_LT(n->norm(), cam->max_radius());
  EXPECT_LT((cam->distort(*n) - ghost).norm(), 1e-12);

  // radtan with k3 < 0 folds too; the EuRoC lens never does.
  EXPECT_TRUE(std::isfinite(make_camera_model(radtan_k3())->max_radius()));
  EXPECT_TRUE(std::isinf(make_camera_model(euroc_radtan())->max_radius()));

  // Equidistant k1 = -0.2: d theta_d / d theta = 1 - 0.6 theta^2 vanishes at sqrt(1/0.6).
  CameraCalibration f = fisheye();
  f.distortion_coeffs = {-0.2, 0.0, 0.0, 0.0};
  const auto fcam = make_camera_model(f);
  const double theta_max = std::sqrt(1.0 / 0.6);
  EXPECT_NEAR(fcam->max_radius(), std::tan(theta_max), 1e-9);
  const double max_theta_d = theta_max * (1.0 - 0.2 * theta_max * theta_max);
  EXPECT_TRUE(fcam->undistort(Vec2(0.0, 0.99 * max_theta_d)));
  EXPECT_FALSE(fcam->undistort(Vec2(0.0, 1.01 * max_theta_d)));
}

TEST(Camera, UndistortFailureFlag) {
  const auto fish = make_camera_model(fisheye());
  // Beyond theta_d(90 degrees) there is no point in front of the camera.
  EXPECT_FALSE(fish->undistort(Vec2(1.7, 0.0)));
  EXPECT_FALSE(fish->unproject(Vec2(0.0, 0.0)));  // the image corner sees behind the lens
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& calib : all_models()) {
    const auto cam = make_camera_model(calib);
    EXPECT_FALSE(cam->undistort(Vec2(nan, 0.1)));
    EXPECT_FALSE(cam->unproject(Vec2(10.0, std::numeric_limits<double>::infinity())));
    EXPECT_TRUE(cam->undistort(Vec2::Zero())->isZero(0.0));
  }
}

TEST(Camera, InImageWithBorder) {
  const auto cam = make_camera_model(euroc_radtan());
  EXPECT_TRUE(cam->in_image(Vec2(0, 0)));
  EXPECT_TRUE(cam->in_image(Vec2(751, 479)));
  EXPECT_FALSE(cam->in_image(Vec2(751.01, 10)));
  EXPECT_FALSE(cam->in_image(Vec2(10, 479.01)));
  EXPECT_FALSE(cam->in_image(Vec2(-0.01, 10)));
  EXPECT_TRUE(cam->in_image(Vec2(5, 5), 5.0));
  EXPECT_FALSE(cam->in_image(Vec2(4.9, 100), 5.0));
  EXPECT_TRUE(cam->in_image(Vec2(746, 474), 5.0));
  EXPECT_FALSE(cam->in_image(Vec2(746.1, 100), 5.0));
  EXPECT_FALSE(cam->in_image(Vec2(std::numeric_limits<double>::quiet_NaN(), 100)));
}

// The key a bad calibration is reported under.
std::string rejected_key(const CameraCalibration& calib) {
  try {
    make_camera_model(calib, "rig.yaml");
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "rig.yaml");
    EXPECT_NE(std::string(e.what()).find(e.key()), std::string::npos);
    return e.key();
  }
  return "<accepted>";
}

TEST(Camera, BadCalibrationsRaiseConfigError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    std::string what;
    std::function<void(CameraCalibration&)> edit;
    std::string key;
  };
  const std::vector<Case> cases = {
      {"zero width", [](CameraCalibration& c) { c.width = 0; }, "width"},
      {"negative height", [](CameraCalibration& c) { c.height = -480; }, "height"},
      {"zero fx", [](CameraCalibration& c) { c.fx = 0; }, "fx"},
      {"negative fy", [](CameraCalibration& c) { c.fy = -457.0; }, "fy"},
      {"NaN fx", [nan](CameraCalibration& c) { c.fx = nan; }, "fx"},
      {"infinite fy", [](CameraCalibration& c) { c.fy = std::numeric_limits<double>::infinity(); }, "fy"},
      {"NaN cx", [nan](CameraCalibration& c) { c.cx = nan; }, "cx"},
      {"NaN cy", [nan](CameraCalibration& c) { c.cy = nan; }, "cy"},
      {"radtan with 3", [](CameraCalibration& c) { c.distortion_coeffs.resize(3); }, "distortion_coeffs"},
      {"radtan with 6", [](CameraCalibration& c) { c.distortion_coeffs.resize(6); }, "distortion_coeffs"},
      {"radtan NaN", [nan](CameraCalibration& c) { c.distortion_coeffs[1] = nan; }, "distortion_coeffs"},
      {"equidistant with 5",
       [](CameraCalibration& c) {
         c.distortion = DistortionModel::kEquidistant;
         c.distortion_coeffs.push_back(0.0);
       },
       "distortion_coeffs"},
      {"equidistant with none",
       [](CameraCalibration& c) {
         c.distortion = DistortionModel::kEquidistant;
         c.distortion_coeffs.clear();
       },
       "distortion_coeffs"},
      {"pinhole with coefficients",
       [](CameraCalibration& c) { c.distortion = DistortionModel::kNone; },
       "distortion_coeffs"},
      {"unknown model", [](CameraCalibration& c) { c.distortion = static_cast<DistortionModel>(42); },
       "distortion_model"},
  };
  for (const auto& c : cases) {
    CameraCalibration calib = euroc_radtan();
    c.edit(calib);
    EXPECT_EQ(rejected_key(calib), c.key) << c.what;
  }
  // Allowed: radtan with 5 values, none with an explicit list of zeros.
  CameraCalibration zeros = pinhole();
  zeros.distortion_coeffs = {0, 0, 0, 0};
  EXPECT_EQ(rejected_key(zeros), "<accepted>");
  EXPECT_EQ(rejected_key(radtan_k3()), "<accepted>");
}

TEST(Camera, ErrorMessageNamesCameraKeyAndRange) {
  CameraCalibration c = fisheye();
  c.distortion_coeffs = {0.1, 0.2, 0.3};
  const auto e = navaid::testing::expect_throw<ConfigError>([&] { make_camera_model(c); });
  ASSERT_TRUE(e.has_value());
  const std::string message = e->what();
  EXPECT_NE(message.find("fisheye"), std::string::npos) << message;
  EXPECT_NE(message.find("distortion_coeffs"), std::string::npos) << message;
  EXPECT_NE(message.find("4 values"), std::string::npos) << message;
  EXPECT_NE(message.find("got 3"), std::string::npos) << message;
}

}  // namespace
}  // namespace navaid
