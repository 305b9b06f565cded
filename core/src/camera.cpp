#include "navaid/core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"

namespace navaid {
namespace {

using Vec2 = CameraModel::Vec2;
using Mat2 = CameraModel::Mat2;

constexpr double kHalfPi = 1.57079632679489661923;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

// First angle in (0, pi/2) where `slope` (the derivative of the distorted radius with respect to
// the undistorted one) stops being positive, or pi/2 if it never does. A fine scan then bisection:
// low-order polynomials cannot hide a sign change inside one 1/4096 step except at a tangency.
double first_fold_angle(const std::function<double(double)>& slope) {
  constexpr int kSteps = 4096;
  double lo = 0.0;
  for (int i = 1; i < kSteps; ++i) {
    const double hi = kHalfPi * i / kSteps;
    if (!(slope(hi) > 0.0)) {
      double a = lo, b = hi;
      for (int k = 0; k < 60; ++k) {
        const double m = 0.5 * (a + b);
        (slope(m) > 0.0 ? a : b) = m;
      }
      return a;
    }
    lo = hi;
  }
  return kHalfPi;
}

class PinholeCamera final : public CameraModel {
 public:
  explicit PinholeCamera(const CameraCalibration& calib) : CameraModel(calib, kInf) {}

  Vec2 distort_impl(const Vec2& normalized, Mat2* J) const override {
    if (J) J->setIdentity();
    return normalized;
  }
  std::optional<Vec2> undistort_impl(const Vec2& distorted) const override { return distorted; }
};

class RadTanCamera final : public CameraModel {
 public:
  explicit RadTanCamera(const CameraCalibration& calib) : RadTanCamera(calib, coefficients(calib)) {}

  Vec2 distort_impl(const Vec2& n, Mat2* J) const override {
    const double x = n.x(), y = n.y();
    const double x2 = x * x, y2 = y * y, xy = x * y, r2 = x2 + y2;
    const double radial = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
    const Vec2 d(x * radial + 2.0 * p1_ * xy + p2_ * (r2 + 2.0 * x2),
                 y * radial + p1_ * (r2 + 2.0 * y2) + 2.0 * p2_ * xy);
    if (J) {
      // d(radial)/dx = dradial * x, likewise for y.
      const double dradial = 2.0 * k1_ + r2 * (4.0 * k2_ + 6.0 * k3_ * r2);
      const double cross = dradial * xy + 2.0 * p1_ * x + 2.0 * p2_ * y;
      *J << radial + dradial * x2 + 2.0 * p1_ * y + 6.0 * p2_ * x, cross,  //
          cross, radial + dradial * y2 + 6.0 * p1_ * y + 2.0 * p2_ * x;
    }
    return d;
  }

  std::optional<Vec2> undistort_impl(const Vec2& distorted) const override {
    const double tol = kUndistortTolerance * std::max(1.0, distorted.norm());
    const double max_r2 = max_radius() * max_radius();
    Vec2 x = distorted;  // distortion is a perturbation of the identity near the centre
    Mat2 J;
    Vec2 err = distort_impl(x, &J) - distorted;
    for (int it = 0; it < 50; ++it) {
      if (err.norm() <= tol) {
        // A solution past the fold is a ghost: the same pixel seen from outside the lens's range.
        if (J.determinant() > 0.0 && x.squaredNorm() < max_r2) return x;
        return std::nullopt;
      }
      const double det = J.determinant();
      if (!(std::abs(det) > 1e-300)) return std::nullopt;
      const Vec2 step = -J.inverse() * err;
      // Backtrack so that each step reduces the residual and stays inside the monotonic region.
      double scale = 1.0;
      bool accepted = false;
      for (int k = 0; k < 40 && !accepted; ++k, scale *= 0.5) {
        const Vec2 trial = x + scale * step;
        if (!(trial.squaredNorm() < max_r2)) continue;
        Mat2 J_trial;
        const Vec2 err_trial = distort_impl(trial, &J_trial) - distorted;
        if (err_trial.norm() < err.norm()) {
          x = trial;
          J = J_trial;
          err = err_trial;
          accepted = true;
        }
      }
      if (!accepted) return std::nullopt;
    }
    return std::nullopt;
  }

 private:
  struct Coefficients {
    double k1, k2, p1, p2, k3;
  };
  static Coefficients coefficients(const CameraCalibration& calib) {
    const auto& d = calib.distortion_coeffs;
    return {d[0], d[1], d[2], d[3], d.size() > 4 ? d[4] : 0.0};
  }
  RadTanCamera(const CameraCalibration& calib, const Coefficients& c)
      : CameraModel(calib, fold_radius(c)), k1_(c.k1), k2_(c.k2), p1_(c.p1), p2_(c.p2), k3_(c.k3) {}

  // Radial part only: d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)], scanned over theta = atan(r) so
  // that the whole half-line r >= 0 is covered.
  static double fold_radius(const Coefficients& c) {
    const double theta = first_fold_angle([&c](double t) {
      const double r2 = std::tan(t) * std::tan(t);
      return 1.0 + r2 * (3.0 * c.k1 + r2 * (5.0 * c.k2 + r2 * 7.0 * c.k3));
    });
    return theta < kHalfPi ? std::tan(theta) : kInf;
  }

  double k1_, k2_, p1_, p2_, k3_;
};

class EquidistantCamera final : public CameraModel {
 public:
  explicit EquidistantCamera(const CameraCalibration& calib)
      : EquidistantCamera(calib, calib.distortion_coeffs, fold_angle(calib.distortion_coeffs)) {}

  // theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8) and
  // the distorted point is (theta_d / r) * n = s(r) * n with s = h(r) g(theta^2), h = atan(r)/r.
  Vec2 distort_impl(const Vec2& n, Mat2* J) const override {
    const double r2 = n.squaredNorm();
    const double r = std::sqrt(r2);
    const double theta = std::atan(r);
    const double t2 = theta * theta;
    const double g = 1.0 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3])));
    // atan(r)/r without 0/0 at the centre.
    const double h = r < 1e-4 ? 1.0 - r2 / 3.0 + r2 * r2 / 5.0 : theta / r;
    const double s = h * g;
    if (J) {
      // J = s I + (s'(r) / r) n n^T, with s'/r = (h'/r) g + 2 h^2 g'(theta^2) / (1 + r^2).
      const double dg = k_[0] + t2 * (2.0 * k_[1] + t2 * (3.0 * k_[2] + t2 * 4.0 * k_[3]));
      const double ds_over_r = h_prime_over_r(r, r2, theta) * g + 2.0 * h * h * dg / (1.0 + r2);
      *J = s * Mat2::Identity() + ds_over_r * n * n.transpose();
    }
    return s * n;
  }

  std::optional<Vec2> undistort_impl(const Vec2& distorted) const override {
    const double theta_d = distorted.norm();
    if (!(theta_d < max_theta_d_)) return std::nullopt;
    // theta_d(theta) is increasing on [0, max_theta_), so Newton safeguarded by bisection on
    // that bracket always converges.
    const double tol = kUndistortTolerance * std::max(1.0, theta_d);
    double lo = 0.0, hi = max_theta_;
    double theta = theta_d < hi ? theta_d : 0.5 * hi;
    for (int it = 0; it < 100; ++it) {
      const double f = distorted_angle(theta) - theta_d;
      if (std::abs(f) <= tol) {
        if (!(theta < kHalfPi)) return std::nullopt;
        return distorted * (std::tan(theta) / theta_d);
      }
      (f < 0.0 ? lo : hi) = theta;
      double next = theta - f / slope(k_, theta);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (next == theta) break;  // bracket exhausted at machine precision without reaching tol
      theta = next;
    }
    return std::nullopt;
  }

 private:
  EquidistantCamera(const CameraCalibration& calib, const std::vector<double>& k, double max_theta)
      : CameraModel(calib, max_theta < kHalfPi ? std::tan(max_theta) : kInf),
        k_{k[0], k[1], k[2], k[3]},
        max_theta_(max_theta),
        max_theta_d_(distorted_angle(max_theta)) {}

  static double fold_angle(const std::vector<double>& k) {
    return first_fold_angle([&k](double theta) { return slope(k.data(), theta); });
  }

  // d theta_d / d theta.
  static double slope(const double* k, double theta) {
    const double t2 = theta * theta;
    return 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
  }

  double distorted_angle(double theta) const {
    const double t2 = theta * theta;
    return theta * (1.0 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3]))));
  }

  // h'(r)/r for h = atan(r)/r, i.e. (r/(1+r^2) - atan r)/r^3: cancellation makes the closed form
  // lose ~eps/r^2, so use its alternating series sum_n (-1)^n 2n r^(2n-2)/(2n+1) near 0.
  static double h_prime_over_r(double r, double r2, double theta) {
    if (r < 0.1) {
      double sum = 0.0;
      for (int n = 9; n >= 1; --n) sum = (n % 2 ? -1.0 : 1.0) * 2.0 * n / (2.0 * n + 1.0) + r2 * sum;
      return sum;
    }
    return (r / (1.0 + r2) - theta) / (r2 * r);
  }

  double k_[4];
  double max_theta_;
  double max_theta_d_;
};

}  // namespace

CameraModel::CameraModel(CameraCalibration calib, double max_radius)
    : calib_(std::move(calib)), max_radius_(max_radius), max_radius2_(max_radius * max_radius) {}

Eigen::Matrix3d CameraModel::K() const {
  Eigen::Matrix3d k;
  k << calib_.fx, 0, calib_.cx,  //
      0, calib_.fy, calib_.cy,   //
      0, 0, 1;
  return k;
}

std::optional<CameraModel::Vec2> CameraModel::project(const Vec3& p_C, Mat23* J) const {
  if (!(p_C.z() > kMinDepth)) return std::nullopt;  // also rejects NaN
  const double inv_z = 1.0 / p_C.z();
  const Vec2 n(p_C.x() * inv_z, p_C.y() * inv_z);
  if (!(n.squaredNorm() < max_radius2_)) return std::nullopt;
  if (!J) return pixel_from_distorted(distort(n));
  Mat2 Jd;
  const Vec2 d = distort(n, &Jd);
  Mat23 Jn;
  Jn << inv_z, 0, -n.x() * inv_z,  //
      0, inv_z, -n.y() * inv_z;
  *J = Eigen::Vector2d(calib_.fx, calib_.fy).asDiagonal() * Jd * Jn;
  return pixel_from_distorted(d);
}

std::optional<CameraModel::Vec2> CameraModel::undistort(const Vec2& distorted) const {
  if (!distorted.allFinite()) return std::nullopt;
  if (distorted.isZero(0.0)) return distorted;  // every model leaves the centre in place
  return undistort_impl(distorted);
}

std::optional<Vec3> CameraModel::unproject(const Vec2& pixel) const {
  const std::optional<Vec2> n = undistort(distorted_from_pixel(pixel));
  if (!n) return std::nullopt;
  return Vec3(n->x(), n->y(), 1.0).normalized();
}

bool CameraModel::in_image(const Vec2& pixel, double border) const {
  return pixel.x() >= border && pixel.y() >= border && pixel.x() <= calib_.width - 1 - border &&
         pixel.y() <= calib_.height - 1 - border;
}

void validate_camera_calibration(const CameraCalibration& c, const std::string& origin) {
  const std::string where = origin.empty() ? "camera '" + c.name + "'" : origin;
  auto fail = [&where](const std::string& key, const std::string& message) {
    throw ConfigError(where, key, message);
  };
  if (c.width <= 0) fail("width", "must be > 0 [px], got " + std::to_string(c.width));
  if (c.height <= 0) fail("height", "must be > 0 [px], got " + std::to_string(c.height));
  // Negated comparisons so that NaN fails too.
  if (!(c.fx > 0.0 && std::isfinite(c.fx))) fail("fx", "must be finite and > 0 [px], got " + number(c.fx));
  if (!(c.fy > 0.0 && std::isfinite(c.fy))) fail("fy", "must be finite and > 0 [px], got " + number(c.fy));
  if (!std::isfinite(c.cx)) fail("cx", "must be finite [px], got " + number(c.cx));
  if (!std::isfinite(c.cy)) fail("cy", "must be finite [px], got " + number(c.cy));

  const auto& d = c.distortion_coeffs;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (!std::isfinite(d[i]))
      fail("distortion_coeffs", "value " + std::to_string(i) + " must be finite, got " + number(d[i]));
  const std::string count = std::to_string(d.size());
  switch (c.distortion) {
    case DistortionModel::kNone:
      // Configs often spell "no distortion" as a list of zeros; anything else is a mistake.
      for (double v : d)
        if (v != 0.0)
          fail("distortion_coeffs", "must be empty or all zero when the distortion model is none, got " +
                                        number(v));
      break;
    case DistortionModel::kRadialTangential:
      if (d.size() != 4 && d.size() != 5)
        fail("distortion_coeffs", "radtan needs 4 or 5 values (k1 k2 p1 p2 [k3]), got " + count);
      break;
    case DistortionModel::kEquidistant:
      if (d.size() != 4) fail("distortion_coeffs", "equidistant needs 4 values (k1 k2 k3 k4), got " + count);
      break;
    default:
      fail("distortion_model", "must be one of none, radtan, equidistant");
  }
}

std::unique_ptr<CameraModel> make_camera_model(const CameraCalibration& calib, const std::string& origin) {
  validate_camera_calibration(calib, origin);
  switch (calib.distortion) {
    case DistortionModel::kRadialTangential: return std::make_unique<RadTanCamera>(calib);
    case DistortionModel::kEquidistant: return std::make_unique<EquidistantCamera>(calib);
    case DistortionModel::kNone: break;
  }
  return std::make_unique<PinholeCamera>(calib);
}

}  // namespace navaid
