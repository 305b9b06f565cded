#include "navaid/estimation/gps_registration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <optional>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/core/time.hpp"
#include "navaid/core/number_text.hpp"

namespace navaid::estimation {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr int kMaxGaussNewtonSteps = 20;

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

void check_lat_lon(double lat_deg, double lon_deg, const std::string& what) {
  if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg) || std::abs(lat_deg) > 90.0 || std::abs(lon_deg) > 180.0)
    throw Error(what + ": latitude/longitude must be finite, within [-90, 90] and [-180, 180] deg, found (" +
                number_text(lat_deg) + ", " + number_text(lon_deg) + ")");
}

// East/north of the geodesic from (lat1, lon1) to (lat2, lon2), with the azimuth at the start.
Eigen::Vector2d geodesic_step(double lat1, double lon1, double lat2, double lon2) {
  const GeodesicLine line = geodesic_inverse(lat1, lon1, lat2, lon2);
  const double a = line.azimuth_deg * kDegToRad;  // clockwise from north: east = s sin a
  return line.distance_m * Eigen::Vector2d(std::sin(a), std::cos(a));
}

// One located fix ready for the fit.
struct FitFix {
  std::size_t index = 0;  // into the input pairs
  Vec3 a = Vec3::Zero();  // antenna in W
  Vec3 z = Vec3::Zero();  // eq. 6 ENU; z.z() = 0 when the height is not used
  Mat3 info = Mat3::Zero();  // information; third row/column zero when the height is not used
  double w_h = 0;         // scalar horizontal weight of the closed form (1/sigma^2 when isotropic)
  bool height = false;
};

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;

Vec3 residual(const FitFix& f, const Vec4& x) {
  const Mat3 Rz = Eigen::AngleAxisd(x[0], Vec3::UnitZ()).toRotationMatrix();
  Vec3 r = Rz * f.a + x.tail<3>() - f.z;
  if (!f.height) r.z() = 0.0;
  return r;
}

double mahalanobis(const FitFix& f, const Vec4& x) {
  const Vec3 r = residual(f, x);
  return std::sqrt(std::max(0.0, r.dot(f.info * r)));
}

double robust_weight(RobustLoss loss, double k, double e) {
  switch (loss) {
    case RobustLoss::kNone: return 1.0;
    case RobustLoss::kHuber: return e <= k ? 1.0 : k / e;
    case RobustLoss::kCauchy: return 1.0 / (1.0 + (e / k) * (e / k));
  }
  return 1.0;
}

// Eq. 7 in closed form with scalar weights omega_i w_i: weighted centroids, yaw from the weighted
// cross/dot sums of the centred points; t_z the weighted mean height offset.
Vec4 closed_form(const std::vector<FitFix>& fixes, const std::vector<double>& omega, bool with_height) {
  double W = 0, Wu = 0, tz = 0;
  Eigen::Vector2d a_mean = Eigen::Vector2d::Zero(), z_mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const double w = omega[i] * fixes[i].w_h;
    W += w;
    a_mean += w * fixes[i].a.head<2>();
    z_mean += w * fixes[i].z.head<2>();
    if (with_height && fixes[i].height) {
      const double wu = omega[i] * fixes[i].info(2, 2);
      Wu += wu;
      tz += wu * (fixes[i].z.z() - fixes[i].a.z());
    }
  }
  a_mean /= W;
  z_mean /= W;
  double C = 0, S = 0;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const double w = omega[i] * fixes[i].w_h;
    const Eigen::Vector2d A = fixes[i].a.head<2>() - a_mean, Z = fixes[i].z.head<2>() - z_mean;
    C += w * A.dot(Z);
    S += w * (A.x() * Z.y() - A.y() * Z.x());
  }
  const double yaw = std::atan2(S, C);
  const Eigen::Vector2d t = z_mean - Eigen::Rotation2Dd(yaw) * a_mean;
  return Vec4(yaw, t.x(), t.y(), Wu > 0 ? tz / Wu : 0.0);
}

// Weighted normal equations of the GpsPositionFactor residual at x; n = 3 or 4 parameters.
void normal_equations(const std::vector<FitFix>& fixes, const std::vector<double>& omega, const Vec4& x, Mat4& H,
                      Vec4& g) {
  const Mat3 Rz = Eigen::AngleAxisd(x[0], Vec3::UnitZ()).toRotationMatrix();
  H.setZero();
  g.setZero();
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const Vec3 Ra = Rz * fixes[i].a;
    Eigen::Matrix<double, 3, 4> J;
    J.col(0) = Vec3(-Ra.y(), Ra.x(), 0.0);  // d(Rz a)/d yaw = e_z x (Rz a)
    J.rightCols<3>() = Mat3::Identity();
    const Eigen::Matrix<double, 4, 3> JtL = omega[i] * J.transpose() * fixes[i].info;
    H += JtL * J;
    g += JtL * residual(fixes[i], x);
  }
}

Vec4 gauss_newton(const std::vector<FitFix>& fixes, const std::vector<double>& omega, Vec4 x, int n) {
  Mat4 H;
  Vec4 g;
  for (int step = 0; step < kMaxGaussNewtonSteps; ++step) {
    normal_equations(fixes, omega, x, H, g);
    Vec4 dx = Vec4::Zero();
    dx.head(n) = -H.topLeftCorner(n, n).ldlt().solve(g.head(n));
    x += dx;
    x[0] = wrap_angle(x[0]);
    if (dx.lpNorm<Eigen::Infinity>() < 1e-13 * (1.0 + x.tail<3>().lpNorm<Eigen::Infinity>())) break;
  }
  return x;
}

std::vector<double> robust_weights(const std::vector<FitFix>& fixes, const Vec4& x, RobustLoss loss, double k) {
  std::vector<double> omega(fixes.size());
  for (std::size_t i = 0; i < fixes.size(); ++i) omega[i] = robust_weight(loss, k, mahalanobis(fixes[i], x));
  return omega;
}

// Sandwich covariance H^-1 B H^-1 of the weighted estimate when fix errors correlate in time:
// B = sum_ij G_i rho_ij G_j^T, G_i = omega_i J_i^T Lambda_i L_i (Sigma_i = L_i L_i^T),
// rho_ij = exp(-|t_i - t_j| / tau). With rho = identity and unit weights B = H.
Eigen::MatrixXd correlated_covariance(const std::vector<FitFix>& fixes, const std::vector<double>& omega,
                                      const std::vector<Mat3>& chol, const std::vector<double>& t_s, const Vec4& x,
                                      const Mat4& H, int n, double tau) {
  const Mat3 Rz = Eigen::AngleAxisd(x[0], Vec3::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Matrix<double, 4, 3>> G(fixes.size());
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const Vec3 Ra = Rz * fixes[i].a;
    Eigen::Matrix<double, 3, 4> J;
    J.col(0) = Vec3(-Ra.y(), Ra.x(), 0.0);
    J.rightCols<3>() = Mat3::Identity();
    G[i] = omega[i] * J.transpose() * fixes[i].info * chol[i];
  }
  Mat4 B = Mat4::Zero();
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    Eigen::Matrix<double, 4, 3> sum = G[i];  // rho_ii = 1
    for (std::size_t j = 0; j < fixes.size(); ++j)
      if (j != i) sum += std::exp(-std::abs(t_s[i] - t_s[j]) / tau) * G[j];
    B += sum * G[i].transpose();
  }
  const Eigen::MatrixXd Hinv = H.topLeftCorner(n, n).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd P = Hinv * B.topLeftCorner(n, n) * Hinv;
  return 0.5 * (P + P.transpose());
}

Mat3 checked_covariance(const Mat3& cov, std::size_t index) {
  const std::string where = "register_gps_to_world: pair " + std::to_string(index) + ": fix covariance_enu ";
  if (!cov.allFinite()) throw Error(where + "is not finite");
  if (!cov.isApprox(cov.transpose(), 1e-9)) throw Error(where + "is not symmetric");
  if (Eigen::LLT<Mat3>(cov).info() != Eigen::Success) throw Error(where + "is not positive definite");
  return cov;
}

}  // namespace

void validate(const GpsRegistrationOptions& o, const std::string& source) {
  if (!(o.robust_threshold > 0.0) || !std::isfinite(o.robust_threshold))
    throw ConfigError(source, "robust_threshold", "expected a finite value > 0 sigma, found " + number_text(o.robust_threshold));
  if (o.min_fixes < 2)
    throw ConfigError(source, "min_fixes", "expected an integer >= 2, found " + std::to_string(o.min_fixes));
  if (!(o.min_spread_m > 0.0) || !std::isfinite(o.min_spread_m))
    throw ConfigError(source, "min_spread_m", "expected a finite value > 0 m, found " + number_text(o.min_spread_m));
  if (!(o.max_yaw_sigma_rad > 0.0) || !std::isfinite(o.max_yaw_sigma_rad))
    throw ConfigError(source, "max_yaw_sigma_rad", "expected a finite value > 0 rad, found " + number_text(o.max_yaw_sigma_rad));
  if (!(o.error_correlation_time_s >= 0.0) || !std::isfinite(o.error_correlation_time_s))
    throw ConfigError(source, "error_correlation_time_s",
                      "expected a finite value >= 0 s, found " + number_text(o.error_correlation_time_s));
  if (o.max_iterations < 1)
    throw ConfigError(source, "max_iterations", "expected an integer >= 1, found " + std::to_string(o.max_iterations));
}

const char* to_string(GpsRegistrationStatus status) {
  switch (status) {
    case GpsRegistrationStatus::kRegistered: return "registered";
    case GpsRegistrationStatus::kTooFewFixes: return "too few fixes";
    case GpsRegistrationStatus::kInsufficientMotion: return "insufficient motion";
    case GpsRegistrationStatus::kYawTooUncertain: return "yaw too uncertain";
  }
  return "unknown";
}

SE3 GpsRegistration::T_ENU_W() const {
  return SE3(Quat(Eigen::AngleAxisd(alignment[0], Vec3::UnitZ())), alignment.tail<3>());
}

std::vector<Vec3> geodesic_enu(const std::vector<GpsFix>& fixes, const GeodeticOrigin& origin, GeodesicPath path) {
  check_lat_lon(origin.latitude_deg, origin.longitude_deg, "geodesic_enu: origin");
  if (!std::isfinite(origin.height_m)) throw Error("geodesic_enu: origin height is not finite");
  std::vector<Vec3> enu;
  enu.reserve(fixes.size());
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const GpsFix& f = fixes[i];
    const std::string what = "geodesic_enu: fix " + std::to_string(i);
    if (f.mode == GpsFixMode::kNoFix) throw Error(what + " has no position (kNoFix)");
    check_lat_lon(f.latitude_deg, f.longitude_deg, what);
    Eigen::Vector2d en;
    if (path == GeodesicPath::kChained && i > 0) {
      en = enu.back().head<2>() +
           geodesic_step(fixes[i - 1].latitude_deg, fixes[i - 1].longitude_deg, f.latitude_deg, f.longitude_deg);
    } else {
      en = geodesic_step(origin.latitude_deg, origin.longitude_deg, f.latitude_deg, f.longitude_deg);
    }
    const std::optional<double> h = ellipsoidal_height_m(f);
    enu.emplace_back(en.x(), en.y(), h ? *h - origin.height_m : std::nan(""));
  }
  return enu;
}

GpsRegistration register_gps_to_world(const std::vector<GpsRegistrationPair>& pairs, const GeodeticOrigin& origin,
                                      const GpsRegistrationOptions& options) {
  validate(options);
  GpsRegistration out;
  out.weights.assign(pairs.size(), 0.0);

  std::vector<GpsFix> located;
  std::vector<FitFix> fixes;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const GpsRegistrationPair& p = pairs[i];
    if (!p.antenna_W.allFinite())
      throw Error("register_gps_to_world: pair " + std::to_string(i) + ": antenna_W is not finite");
    if (p.fix.mode == GpsFixMode::kNoFix) {
      ++out.skipped_no_fix;
      continue;
    }
    FitFix f;
    f.index = i;
    f.a = p.antenna_W;
    f.info = checked_covariance(p.fix.covariance_enu, i).inverse();
    located.push_back(p.fix);
    fixes.push_back(f);
  }
  const std::vector<Vec3> enu = geodesic_enu(located, origin, options.path);
  bool any_height = false;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    fixes[i].height = options.estimate_height && std::isfinite(enu[i].z());
    any_height = any_height || fixes[i].height;
  }
  out.height_estimated = any_height;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    FitFix& f = fixes[i];
    const Mat3 cov = pairs[f.index].fix.covariance_enu;
    if (!f.height) {  // marginalize the height out: information of the horizontal block alone
      f.info.setZero();
      f.info.topLeftCorner<2, 2>() = cov.topLeftCorner<2, 2>().inverse();
    }
    f.z = Vec3(enu[i].x(), enu[i].y(), f.height ? enu[i].z() : 0.0);
    f.w_h = 2.0 / cov.topLeftCorner<2, 2>().trace();
  }
  out.used_fixes = fixes.size();
  if (fixes.size() < options.min_fixes) {
    out.status = GpsRegistrationStatus::kTooFewFixes;
    return out;
  }

  // Yaw is observable only once the W positions spread out horizontally.
  double W = 0, spread2 = 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const FitFix& f : fixes) {
    W += f.w_h;
    centroid += f.w_h * f.a.head<2>();
  }
  centroid /= W;
  for (const FitFix& f : fixes) spread2 += f.w_h * (f.a.head<2>() - centroid).squaredNorm();
  out.spread_m = std::sqrt(spread2 / W);
  if (out.spread_m < options.min_spread_m) {
    out.status = GpsRegistrationStatus::kInsufficientMotion;
    return out;
  }

  const int n = any_height ? 4 : 3;
  std::vector<double> omega(fixes.size(), 1.0);
  Vec4 x = gauss_newton(fixes, omega, closed_form(fixes, omega, any_height), n);

  // IRLS; the Cauchy loss is not convex, so it starts from the (unique) Huber solution.
  std::vector<RobustLoss> stages;
  if (options.loss != RobustLoss::kNone) stages.push_back(RobustLoss::kHuber);
  if (options.loss == RobustLoss::kCauchy) stages.push_back(RobustLoss::kCauchy);
  for (const RobustLoss stage : stages) {
    for (int it = 0; it < options.max_iterations; ++it) {
      const std::vector<double> next = robust_weights(fixes, x, stage, options.robust_threshold);
      double change = 0;
      for (std::size_t i = 0; i < next.size(); ++i) change = std::max(change, std::abs(next[i] - omega[i]));
      omega = next;
      ++out.iterations;
      if (change < 1e-12) break;
      x = gauss_newton(fixes, omega, x, n);
    }
  }
  if (stages.empty()) out.iterations = 1;

  Mat4 H;
  Vec4 g;
  normal_equations(fixes, omega, x, H, g);
  out.alignment = x;
  if (options.error_correlation_time_s > 0.0) {
    std::vector<Mat3> chol;
    std::vector<double> t_s;
    for (const FitFix& f : fixes) {
      const GpsFix& fix = pairs[f.index].fix;
      chol.push_back(fix.covariance_enu.llt().matrixL());
      t_s.push_back(ns_to_seconds(fix.t - pairs[fixes.front().index].fix.t));  // small numbers: exact differences
    }
    out.covariance = correlated_covariance(fixes, omega, chol, t_s, x, H, n, options.error_correlation_time_s);
  } else {
    out.covariance = H.topLeftCorner(n, n).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  }
  out.yaw_sigma_rad = std::sqrt(std::max(0.0, out.covariance(0, 0)));
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    out.weights[fixes[i].index] = omega[i];
    const double e = mahalanobis(fixes[i], x);
    out.weighted_chi2 += omega[i] * e * e;
  }
  out.status = out.yaw_sigma_rad <= options.max_yaw_sigma_rad ? GpsRegistrationStatus::kRegistered
                                                               : GpsRegistrationStatus::kYawTooUncertain;
  return out;
}

}  // namespace navaid::estimation
