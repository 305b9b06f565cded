#pragma once
// Private to the initialization: OpenCV's (rvec, tvec) pose, as solvePnP returns it, in Eigen.
#include <optional>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

/// Rotation and translation of x_cam = R x_obj + t from a Rodrigues vector and a translation;
/// nullopt when either is not finite.
inline std::optional<std::pair<Mat3, Vec3>> pose_from_rodrigues(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Mat3 R;
  Vec3 t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  if (!R.allFinite() || !t.allFinite()) return std::nullopt;
  return std::make_pair(R, t);
}

}  // namespace navaid::estimation
