#pragma once
// Camera projection models built from a CameraCalibration: pinhole without distortion,
// radial-tangential ("radtan": k1 k2 p1 p2 [k3], OpenCV / Kalibr) and equidistant (k1..k4,
// Kalibr "equidistant" = OpenCV fisheye).
//
// Coordinates:
//  - camera frame C: x right, y down, z forward (optical axis);
//  - normalized: (x/z, y/z), the undistorted point on the z = 1 plane;
//  - distorted normalized: the normalized point after the lens distortion, K^-1 * pixel;
//  - pixel (u, v) = (column, row), the centre of the top-left pixel is (0, 0) (OpenCV, Kalibr).
//
// Models are immutable after construction; every method is const and safe to call from several
// threads. Hold one as std::shared_ptr<const CameraModel> to share it.
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"

namespace navaid {

class CameraModel {
 public:
  using Vec2 = Eigen::Vector2d;
  using Mat2 = Eigen::Matrix2d;
  using Mat23 = Eigen::Matrix<double, 2, 3>;

  /// Points with z <= kMinDepth [m] are behind (or on) the image plane and do not project.
  static constexpr double kMinDepth = 1e-9;
  /// undistort() stops when |distort(x) - distorted| <= kUndistortTolerance * max(1, |distorted|).
  static constexpr double kUndistortTolerance = 1e-12;

  virtual ~CameraModel() = default;

  const CameraCalibration& calibration() const { return calib_; }
  const std::string& name() const { return calib_.name; }
  DistortionModel distortion() const { return calib_.distortion; }
  int width() const { return calib_.width; }
  int height() const { return calib_.height; }
  double fx() const { return calib_.fx; }
  double fy() const { return calib_.fy; }
  double cx() const { return calib_.cx; }
  double cy() const { return calib_.cy; }
  Eigen::Matrix3d K() const;  ///< intrinsic matrix (no skew)

  /// Largest undistorted normalized radius |(x/z, y/z)| for which the radial distortion is still
  /// monotonic (infinity when it is everywhere). Beyond it the polynomial folds back and a point
  /// far outside the field of view would land inside the image, so project() refuses it.
  double max_radius() const { return max_radius_; }

  /// Pixel of a point in the camera frame, and optionally d(pixel)/d(p_C). nullopt when the point
  /// is not in front of the camera (z <= kMinDepth), beyond max_radius() or not finite. The pixel
  /// may lie outside the image: check in_image().
  std::optional<Vec2> project(const Vec3& p_C, Mat23* J = nullptr) const;

  /// Unit bearing vector (z > 0) of a pixel, or nullopt when undistort() fails. Pixels outside
  /// the image are unprojected too (the model extends beyond the sensor). Divide by z for the
  /// normalized point.
  std::optional<Vec3> unproject(const Vec2& pixel) const;

  /// Lens distortion of a normalized point, and optionally d(distorted)/d(normalized). Pure
  /// formula: no validity check (see max_radius()).
  Vec2 distort(const Vec2& normalized, Mat2* J = nullptr) const { return distort_impl(normalized, J); }

  /// Inverse of distort() by safeguarded Newton iterations to kUndistortTolerance. nullopt (the
  /// failure flag) when the input is not finite, the iterations do not converge, or no solution
  /// lies within max_radius() (the pixel is outside what the lens model can image).
  std::optional<Vec2> undistort(const Vec2& distorted) const;

  /// Pixel <-> distorted normalized coordinates through the intrinsics only.
  Vec2 pixel_from_distorted(const Vec2& distorted) const {
    return Vec2(calib_.fx * distorted.x() + calib_.cx, calib_.fy * distorted.y() + calib_.cy);
  }
  Vec2 distorted_from_pixel(const Vec2& pixel) const {
    return Vec2((pixel.x() - calib_.cx) / calib_.fx, (pixel.y() - calib_.cy) / calib_.fy);
  }

  /// True when border <= u <= width - 1 - border and likewise for v (pixel centres), so that a
  /// patch of half-size `border` around the pixel stays inside the image. False for NaN.
  bool in_image(const Vec2& pixel, double border = 0.0) const;

 protected:
  CameraModel(CameraCalibration calib, double max_radius);
  CameraModel(const CameraModel&) = default;
  CameraModel& operator=(const CameraModel&) = delete;

  // Non-virtual public wrappers keep the default argument and the input checks in one place.
  virtual Vec2 distort_impl(const Vec2& normalized, Mat2* J) const = 0;
  /// Called with a finite, nonzero point.
  virtual std::optional<Vec2> undistort_impl(const Vec2& distorted) const = 0;

 private:
  CameraCalibration calib_;
  double max_radius_;
  double max_radius2_;
};

/// Checks that a calibration can make a camera model; throws ConfigError naming `origin` (the
/// file the calibration came from; "camera '<name>'" when empty), the key and the allowed values:
/// width/height > 0, fx/fy finite and > 0, cx/cy finite, distortion_coeffs finite with 0 values
/// (or all zero) for none, 4 or 5 for radtan, 4 for equidistant.
void validate_camera_calibration(const CameraCalibration& calib, const std::string& origin = {});

/// The model for calib.distortion, after validate_camera_calibration().
std::unique_ptr<CameraModel> make_camera_model(const CameraCalibration& calib, const std::string& origin = {});

}  // namespace navaid
