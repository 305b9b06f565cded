// ViSP stays in this file (thirdparty-notes/visp.md).
#include "navaid/planning/apriltag_detector.hpp"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/detection/vpDetectorAprilTag.h>

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {

vpDetectorAprilTag::vpAprilTagFamily family_of(const std::string& name) {
  if (name == "36h11") return vpDetectorAprilTag::TAG_36h11;
  if (name == "25h9") return vpDetectorAprilTag::TAG_25h9;
  if (name == "16h5") return vpDetectorAprilTag::TAG_16h5;
  throw ConfigError("", "planning.apriltag.family", fmt::format("unknown tag family '{}'; known: 36h11, 25h9, 16h5", name));
}

/// Intersection of the lines a0-a2 and a1-a3 (the diagonals); the corner mean when degenerate.
Eigen::Vector2d diagonal_intersection(const std::array<Eigen::Vector2d, 4>& c) {
  const Eigen::Vector2d d1 = c[2] - c[0];
  const Eigen::Vector2d d2 = c[3] - c[1];
  const double den = d1.x() * d2.y() - d1.y() * d2.x();
  if (std::abs(den) < 1e-12) return 0.25 * (c[0] + c[1] + c[2] + c[3]);
  const Eigen::Vector2d r = c[1] - c[0];
  const double s = (r.x() * d2.y() - r.y() * d2.x()) / den;
  return c[0] + s * d1;
}

}  // namespace

namespace {
const AprilTagDetectorConfig kApriltagDetectorDefaults;
const ConfigKey<std::string> kFamily{"planning.apriltag.family", kApriltagDetectorDefaults.family, {"36h11", "25h9", "16h5"},
                                     "AprilTag family"};
const ConfigKey<double> kQuadDecimate{"planning.apriltag.quad_decimate", kApriltagDetectorDefaults.quad_decimate, {1.0, 8.0},
                                      "> 1 detects quads on a decimated image: faster, shorter range"};
const ConfigKey<double> kQuadSigma{"planning.apriltag.quad_sigma", kApriltagDetectorDefaults.quad_sigma, {0.0, 5.0},
                                   "Gaussian blur before quad detection [px]"};
const ConfigKey<int> kThreads{"planning.apriltag.threads", kApriltagDetectorDefaults.threads, 1, 64, "AprilTag detector threads"};
const ConfigKey<double> kTagSize{"planning.apriltag.tag_size_m", kApriltagDetectorDefaults.tag_size_m, {0.0, 10.0},
                                 "black-square side of the tags [m]; > 0 estimates the tag's pose"};
}  // namespace

ConfigSchema apriltag_detector_config_schema() {
  return ConfigSchema().add(kFamily).add(kQuadDecimate).add(kQuadSigma).add(kThreads).add(kTagSize);
}

AprilTagDetectorConfig read_apriltag_detector_config(const Config& config) {
  AprilTagDetectorConfig c;
  c.family = get(config, kFamily);
  c.quad_decimate = get(config, kQuadDecimate);
  c.quad_sigma = get(config, kQuadSigma);
  c.threads = get(config, kThreads);
  c.tag_size_m = get(config, kTagSize);
  return c;
}

struct AprilTagDetector::Impl {
  AprilTagDetectorConfig config;
  vpDetectorAprilTag detector;
  vpImage<unsigned char> image;

  explicit Impl(const AprilTagDetectorConfig& c) : config(c), detector(family_of(c.family)) {
    detector.setAprilTagQuadDecimate(static_cast<float>(c.quad_decimate));
    detector.setAprilTagQuadSigma(static_cast<float>(c.quad_sigma));
    detector.setAprilTagNbThreads(c.threads);
    detector.setAprilTagRefineEdges(true);
    // Tag frame z along the camera's optical axis convention (ViSP's default is the older one).
    detector.setZAlignedWithCameraAxis(true);
  }
};

AprilTagDetector::AprilTagDetector(const AprilTagDetectorConfig& config) : impl_(std::make_unique<Impl>(config)) {
  if (!(config.quad_decimate >= 1.0) || config.threads < 1 || config.tag_size_m < 0.0) {
    throw Error("AprilTagDetector: quad_decimate >= 1, threads >= 1 and tag_size_m >= 0 are needed");
  }
}

AprilTagDetector::~AprilTagDetector() = default;

std::vector<AprilTagDetection> AprilTagDetector::detect(const ImageU8& gray, const CameraModel* camera) {
  if (gray.channels != 1) throw Error(fmt::format("AprilTagDetector: needs a grey image, got {} channels", gray.channels));
  if (gray.empty()) return {};
  vpImage<unsigned char>& I = impl_->image;
  I.resize(static_cast<unsigned>(gray.height), static_cast<unsigned>(gray.width));
  std::memcpy(I.bitmap, gray.data(), gray.pixels.size());

  vpDetectorAprilTag& det = impl_->detector;
  std::vector<AprilTagDetection> out;
  if (!det.detect(I)) return out;
  const std::vector<int> ids = det.getTagsId();
  const std::vector<std::vector<vpImagePoint>> corners = det.getTagsCorners();
  vpCameraParameters cam;
  const bool want_pose = impl_->config.tag_size_m > 0.0 && camera != nullptr;
  // ViSP's corners are in AprilTag's +0.5 convention (below): the principal point moves with them.
  if (want_pose) cam.initPersProjWithoutDistortion(camera->fx(), camera->fy(), camera->cx() + 0.5, camera->cy() + 0.5);
  for (std::size_t i = 0; i < ids.size() && i < corners.size(); ++i) {
    if (corners[i].size() != 4) continue;
    AprilTagDetection d;
    d.id = ids[i];
    // AprilTag puts pixel centres at +0.5 (the image's top-left corner is (0, 0)); core's
    // convention puts the top-left pixel's centre at (0, 0). Measured on drawn tags: +0.5 px
    // in u and v before this shift, < 0.1 px after (test_apriltag_detector.cpp).
    for (std::size_t k = 0; k < 4; ++k) {
      d.corners_px[k] = Eigen::Vector2d(corners[i][k].get_u() - 0.5, corners[i][k].get_v() - 0.5);
    }
    d.centre_px = diagonal_intersection(d.corners_px);
    if (want_pose) {
      vpHomogeneousMatrix cMo;
      if (det.getPose(i, impl_->config.tag_size_m, cam, cMo)) {
        Mat3 R;
        Vec3 t;
        for (unsigned r = 0; r < 3; ++r) {
          for (unsigned c = 0; c < 3; ++c) R(r, c) = cMo[r][c];
          t(r) = cMo[r][3];
        }
        d.T_C_tag = SE3(R, t);
      }
    }
    out.push_back(d);
  }
  std::sort(out.begin(), out.end(), [](const AprilTagDetection& a, const AprilTagDetection& b) { return a.id < b.id; });
  return out;
}

std::optional<AprilTagDetection> find_tag(const std::vector<AprilTagDetection>& detections, int id) {
  for (const AprilTagDetection& d : detections) {
    if (d.id == id) return d;
  }
  return std::nullopt;
}

}  // namespace navaid::planning
