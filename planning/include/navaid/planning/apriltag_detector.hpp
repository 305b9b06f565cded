#pragma once
// AprilTag detection for hand guidance's target object: a tag of the tag36h11 family stuck on
// the object marks it (W-ROMA's object detector [24] is a CNN we do not have; a fiducial gives
// the same output, a centre and a box, on real images without a model). Wraps ViSP's
// vpDetectorAprilTag (thirdparty-notes/visp.md); this header speaks core and Eigen types only.
//
// Pixel convention: core/camera.hpp's, the centre of the top-left pixel is (0, 0). The centre is
// the intersection of the tag's diagonals (the projective centre of the square, not the mean of
// the corners, which is biased under perspective).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/camera.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/image.hpp"

namespace navaid::planning {

struct AprilTagDetection {
  int id = -1;
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 4> corners_px;  ///< in the detector's order (ViSP / AprilTag 3)
  /// Pose of the tag in the camera frame (tag frame: origin at the centre, z out of the printed
  /// face toward the camera's side, ViSP's convention), when a tag size and a camera were given.
  std::optional<SE3> T_C_tag;
};

struct AprilTagDetectorConfig {
  std::string family = "36h11";   ///< 36h11 | 25h9 | 16h5
  double quad_decimate = 1.0;     ///< >1 detects quads on a decimated image: faster, shorter range
  double quad_sigma = 0.0;        ///< Gaussian blur before quad detection [px]
  int threads = 1;
  double tag_size_m = 0.0;        ///< black-square side [m]; > 0 asks for T_C_tag
};

/// Keys planning.apriltag.family, quad_decimate [1, 8], quad_sigma [0, 5], threads [1, 64],
/// tag_size_m [0, 10].
AprilTagDetectorConfig read_apriltag_detector_config(const Config& config);

class AprilTagDetector {
 public:
  explicit AprilTagDetector(const AprilTagDetectorConfig& config = {});
  ~AprilTagDetector();
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  /// All tags in an 8-bit grey image (one channel; navaid::Error otherwise). `camera` (pinhole
  /// intrinsics, no distortion assumed) is needed for T_C_tag only. Sorted by id.
  std::vector<AprilTagDetection> detect(const ImageU8& gray, const CameraModel* camera = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The detection with this id, if any.
std::optional<AprilTagDetection> find_tag(const std::vector<AprilTagDetection>& detections, int id);

}  // namespace navaid::planning
