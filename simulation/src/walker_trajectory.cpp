#include "navaid/simulation/walker_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {
namespace {

const char* const kWhere = "WalkerConfig";

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Quintic smoothstep h (speed shape of a ramp, h(0)=0, h(1)=1, h' and h'' zero at both ends),
// its integral H and derivatives: makes speed, acceleration and jerk continuous.
double ramp_H(double x) { return x * x * x * x * (2.5 - 3.0 * x + x * x); }
double ramp_h(double x) { return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x); }
double ramp_dh(double x) { return 30.0 * x * x * (1.0 - 2.0 * x + x * x); }
double ramp_ddh(double x) { return 60.0 * x - 180.0 * x * x + 120.0 * x * x * x; }

// Value and two time derivatives of a scalar signal.
struct Signal {
  double f = 0, df = 0, ddf = 0;
};

// amplitude * e(t) * sin(w t + phase), where e(t) (gait envelope) has derivatives e, de, dde.
Signal gait_oscillation(double amplitude, double w, double phase, double t, double e, double de, double dde) {
  const double sn = std::sin(w * t + phase), cs = std::cos(w * t + phase);
  return {amplitude * e * sn, amplitude * (de * sn + e * w * cs),
          amplitude * (dde * sn + 2.0 * de * w * cs - e * w * w * sn)};
}

// Composite 5-point Gauss-Legendre on 4 sub-intervals: ample for the smooth |p'(u)| of a span.
template <class F>
double integrate(const F& f, double a, double b) {
  static const double kNodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                   0.9061798459386640};
  static const double kWeights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
  constexpr int kSub = 4;
  const double h = (b - a) / kSub;
  double sum = 0.0;
  for (int i = 0; i < kSub; ++i) {
    const double mid = a + (i + 0.5) * h;
    for (int k = 0; k < 5; ++k) sum += kWeights[k] * f(mid + 0.5 * h * kNodes[k]);
  }
  return 0.5 * h * sum;
}

}  // namespace

WalkerTrajectory::WalkerTrajectory(const std::vector<Eigen::Vector2d>& waypoints, const WalkerConfig& config)
    : config_(config) {
  auto require = [](bool ok, const char* key, const std::string& what) {
    if (!ok) throw ConfigError(kWhere, key, what);
  };
  require(config.speed_mps > 0.0 && std::isfinite(config.speed_mps), "speed_mps", "must be > 0");
  require(config.ramp_time_s > 0.0 && std::isfinite(config.ramp_time_s), "ramp_time_s", "must be > 0");
  require(config.corner_spacing_m > 0.0, "corner_spacing_m", "must be > 0");
  require(config.step_frequency_hz >= 0.0, "step_frequency_hz", "must be >= 0");
  require(config.scan_amplitude_rad == 0.0 || config.scan_period_s > 0.0, "scan_period_s",
          "must be > 0 when scan_amplitude_rad != 0");

  // Densify: straight runs of equally spaced control points make the spline exactly straight
  // there, so only corners are rounded. Repeated waypoints are skipped.
  std::vector<Eigen::Vector2d> pts;
  for (const auto& w : waypoints) {
    require(w.allFinite(), "waypoints", "must be finite");
    if (pts.empty()) {
      pts.push_back(w);
      continue;
    }
    const Eigen::Vector2d a = pts.back();
    const double len = (w - a).norm();
    if (len < 1e-9) continue;
    const int m = std::max(1, static_cast<int>(std::ceil(len / config.corner_spacing_m)));
    for (int k = 1; k <= m; ++k) pts.push_back(a + (w - a) * (static_cast<double>(k) / m));
  }
  require(pts.size() >= 2, "waypoints", "need at least two distinct waypoints");
  if (pts.size() == 2) pts.insert(pts.begin() + 1, 0.5 * (pts[0] + pts[1]));  // room for the reflection

  // Phantom end points by point reflection: the curve then starts/ends exactly at the first/last
  // waypoint, tangent to the first/last segment, with zero curvature there.
  control_.reserve(pts.size() + 4);
  control_.push_back(2.0 * pts.front() - pts[2]);
  control_.push_back(2.0 * pts.front() - pts[1]);
  control_.insert(control_.end(), pts.begin(), pts.end());
  const std::size_t n = pts.size();
  control_.push_back(2.0 * pts.back() - pts[n - 2]);
  control_.push_back(2.0 * pts.back() - pts[n - 3]);

  const int spans = static_cast<int>(control_.size()) - kDegree;
  span_start_s_.assign(static_cast<std::size_t>(spans) + 1, 0.0);
  for (int j = 0; j < spans; ++j) {
    const auto jj = static_cast<std::size_t>(j);
    span_start_s_[jj + 1] = span_start_s_[jj] + span_arc_length(j, 1.0);
  }
  length_ = span_start_s_.back();

  // Short paths: shrink the ramps so that both fit (each ramp covers speed * ramp / 2).
  ramp_ = std::min(config.ramp_time_s, length_ / config.speed_mps);
  duration_ = length_ / config.speed_mps + ramp_;
}

void WalkerTrajectory::spline_derivatives(int span, double x, Eigen::Vector2d d[4]) const {
  // Uniform B-spline of degree 5 from the closed form of the cardinal basis,
  // N(t) = 1/5! sum_j (-1)^j C(6, j) (t - j)_+^5 on [0, 6]; its m-th derivative uses power 5 - m.
  // Control point span + i weighs N(x + 5 - i). Arguments are <= 6, so cancellation is harmless.
  static const double kBinom[7] = {1, 6, 15, 20, 15, 6, 1};
  static const double kInvFact[6] = {1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0};
  for (int k = 0; k < 4; ++k) d[k].setZero();
  for (int i = 0; i <= kDegree; ++i) {
    const double t = x + kDegree - i;
    double w[4] = {0, 0, 0, 0};
    for (int j = 0; j <= kDegree + 1 && j < t; ++j) {
      const double r = t - j, sign = (j % 2 == 0) ? kBinom[j] : -kBinom[j];
      const double r2 = r * r, r3 = r2 * r;
      const double powers[4] = {r3 * r2, r2 * r2, r3, r2};  // r^(5 - m)
      for (int m = 0; m < 4; ++m) w[m] += sign * powers[m] * kInvFact[kDegree - m];
    }
    const Eigen::Vector2d& c = control_[static_cast<std::size_t>(span + i)];
    for (int m = 0; m < 4; ++m) d[m] += w[m] * c;
  }
}

double WalkerTrajectory::span_arc_length(int span, double x) const {
  return integrate(
      [&](double u) {
        Eigen::Vector2d d[4];
        spline_derivatives(span, u, d);
        return d[1].norm();
      },
      0.0, x);
}

double WalkerTrajectory::parameter_at(double s, int* span) const {
  s = std::clamp(s, 0.0, length_);
  const auto it = std::upper_bound(span_start_s_.begin(), span_start_s_.end(), s);
  const int spans = static_cast<int>(span_start_s_.size()) - 1;
  const int j = std::clamp(static_cast<int>(it - span_start_s_.begin()) - 1, 0, spans - 1);
  const double s0 = span_start_s_[static_cast<std::size_t>(j)];
  const double len = span_start_s_[static_cast<std::size_t>(j) + 1] - s0;
  // Newton on span_arc_length(j, x) = s - s0; |p'| > 0 and is nearly constant, so this
  // converges in a few iterations from the linear guess.
  double x = std::clamp((s - s0) / len, 0.0, 1.0);
  for (int it_n = 0; it_n < 30; ++it_n) {
    Eigen::Vector2d d[4];
    spline_derivatives(j, x, d);
    const double step = (span_arc_length(j, x) - (s - s0)) / d[1].norm();
    x = std::clamp(x - step, 0.0, 1.0);
    if (std::abs(step) < 1e-14) break;
  }
  *span = j;
  return x;
}

Eigen::Vector2d WalkerTrajectory::path_point(double s) const { return geometry(s).p; }

WalkerTrajectory::PathGeometry WalkerTrajectory::geometry(double s) const {
  int span = 0;
  const double x = parameter_at(s, &span);
  Eigen::Vector2d d[4];
  spline_derivatives(span, x, d);
  const double g = d[1].norm();  // ds/du
  const double c12 = cross2(d[1], d[2]);
  PathGeometry geo;
  geo.p = d[0];
  geo.tangent = d[1] / g;
  geo.normal = Eigen::Vector2d(-geo.tangent.y(), geo.tangent.x());
  geo.kappa = c12 / (g * g * g);
  // d(kappa)/du = cross(p', p''')/g^3 - 3 cross(p', p'') (p'.p'')/g^5, then divide by ds/du.
  const double dkappa_du = cross2(d[1], d[3]) / (g * g * g) - 3.0 * c12 * d[1].dot(d[2]) / std::pow(g, 5);
  geo.dkappa_ds = dkappa_du / g;
  return geo;
}

WalkerTrajectory::Profile WalkerTrajectory::profile(double t) const {
  const double v = config_.speed_mps;
  Profile p;
  if (t <= 0.0) return p;
  if (t >= duration_) {
    p.s = length_;
    return p;
  }
  if (t < ramp_) {
    const double x = t / ramp_;
    p.s = v * ramp_ * ramp_H(x);
    p.ds = v * ramp_h(x);
    p.dds = v * ramp_dh(x) / ramp_;
    p.ddds = v * ramp_ddh(x) / (ramp_ * ramp_);
  } else if (t > duration_ - ramp_) {
    const double x = (duration_ - t) / ramp_;
    p.s = length_ - v * ramp_ * ramp_H(x);
    p.ds = v * ramp_h(x);
    p.dds = -v * ramp_dh(x) / ramp_;
    p.ddds = v * ramp_ddh(x) / (ramp_ * ramp_);
  } else {
    p.s = 0.5 * v * ramp_ + v * (t - ramp_);
    p.ds = v;
  }
  return p;
}

KinematicState WalkerTrajectory::state(double t) const {
  const Profile pr = profile(t);
  const PathGeometry geo = geometry(pr.s);
  const double v = config_.speed_mps;

  // Gait envelope e = current speed / cruise speed: the gait fades in and out with the ramps.
  const double e = pr.ds / v, de = pr.dds / v, dde = pr.ddds / v;
  const double w_step = 2.0 * M_PI * config_.step_frequency_hz;
  const Signal bob = gait_oscillation(config_.bob_amplitude_m, w_step, 0.0, t, e, de, dde);
  const Signal sway = gait_oscillation(config_.sway_amplitude_m, 0.5 * w_step, 0.0, t, e, de, dde);
  const Signal pitch = gait_oscillation(config_.pitch_amplitude_rad, w_step, 0.5 * M_PI, t, e, de, dde);
  const Signal roll = gait_oscillation(config_.roll_amplitude_rad, 0.5 * w_step, 0.0, t, e, de, dde);
  Signal scan;
  if (config_.scan_amplitude_rad != 0.0) {
    const double ws = 2.0 * M_PI / config_.scan_period_s;
    scan = gait_oscillation(config_.scan_amplitude_rad, ws, 0.0, t, 1.0, 0.0, 0.0);
  }

  // Ground curve c(s(t)) with Frenet relations dT/ds = kappa N, dN/ds = -kappa T.
  const Eigen::Vector2d& T = geo.tangent;
  const Eigen::Vector2d& N = geo.normal;
  const double sd = pr.ds, sdd = pr.dds;
  const Eigen::Vector2d c_d = T * sd;
  const Eigen::Vector2d c_dd = T * sdd + N * (geo.kappa * sd * sd);
  const Eigen::Vector2d n_d = -geo.kappa * sd * T;
  const Eigen::Vector2d n_dd =
      -(geo.dkappa_ds * sd * sd + geo.kappa * sdd) * T - geo.kappa * geo.kappa * sd * sd * N;

  // Position = c + sway * N (lateral, left) + height * z.
  const Eigen::Vector2d p_xy = geo.p + sway.f * N;
  const Eigen::Vector2d v_xy = c_d + sway.df * N + sway.f * n_d;
  const Eigen::Vector2d a_xy = c_dd + sway.ddf * N + 2.0 * sway.df * n_d + sway.f * n_dd;

  KinematicState st;
  const Vec3 p_W(p_xy.x(), p_xy.y(), config_.ground_z_m + config_.mount_height_m + bob.f);
  st.v_W = Vec3(v_xy.x(), v_xy.y(), bob.df);
  st.a_W = Vec3(a_xy.x(), a_xy.y(), bob.ddf);

  // Orientation R = Rz(yaw) Ry(pitch) Rx(roll); yaw = path heading + head scan.
  const double yaw = std::atan2(T.y(), T.x()) + scan.f;
  const double yaw_d = geo.kappa * sd + scan.df;
  const double yaw_dd = geo.dkappa_ds * sd * sd + geo.kappa * sdd + scan.ddf;
  const Mat3 Rz = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 Ry = Eigen::AngleAxisd(pitch.f, Vec3::UnitY()).toRotationMatrix();
  const Mat3 Rx = Eigen::AngleAxisd(roll.f, Vec3::UnitX()).toRotationMatrix();
  st.T_W_B = SE3(Mat3(Rz * Ry * Rx), p_W);

  // omega_B = Rx^T Ry^T z yaw' + Rx^T y pitch' + x roll'; alpha_B is its time derivative using
  // d(Rx^T)/dt = -roll' hat(x) Rx^T and d(Ry^T)/dt = -pitch' hat(y) Ry^T.
  const Vec3 ex = Vec3::UnitX(), ey = Vec3::UnitY(), ez = Vec3::UnitZ();
  const Vec3 zr = Rx.transpose() * Ry.transpose() * ez;  // world z seen in B
  const Vec3 yr = Rx.transpose() * ey;
  st.omega_B = zr * yaw_d + yr * pitch.df + ex * roll.df;
  const Vec3 zr_d = -roll.df * ex.cross(zr) - pitch.df * (Rx.transpose() * ey.cross(Ry.transpose() * ez));
  const Vec3 yr_d = -roll.df * ex.cross(yr);
  st.alpha_B = zr_d * yaw_d + zr * yaw_dd + yr_d * pitch.df + yr * pitch.ddf + ex * roll.ddf;
  return st;
}

}  // namespace navaid::simulation
