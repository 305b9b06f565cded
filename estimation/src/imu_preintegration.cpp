#include "navaid/estimation/imu_preintegration.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {
namespace {

ImuSample interpolate_sample(const ImuSample& a, const ImuSample& b, Timestamp t) {
  const double w = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  ImuSample s;
  s.t = t;
  s.gyro = (1.0 - w) * a.gyro + w * b.gyro;
  s.accel = (1.0 - w) * a.accel + w * b.accel;
  return s;
}

}  // namespace

ImuNoise ImuNoise::from(const ImuCalibration& c) {
  ImuNoise n;
  n.gyro_noise_density = c.gyro_noise_density;
  n.accel_noise_density = c.accel_noise_density;
  n.gyro_random_walk = c.gyro_random_walk;
  n.accel_random_walk = c.accel_random_walk;
  return n;
}

void validate(const ImuNoise& noise, const std::string& source) {
  auto require = [&](double v, const char* key) {
    if (!(v >= 0.0) || !std::isfinite(v)) throw ConfigError(source, key, "must be finite and >= 0");
  };
  require(noise.gyro_noise_density, "gyro_noise_density");
  require(noise.accel_noise_density, "accel_noise_density");
  require(noise.gyro_random_walk, "gyro_random_walk");
  require(noise.accel_random_walk, "accel_random_walk");
  require(noise.max_sample_gap_s, "max_sample_gap");
  if (noise.max_sample_gap_s > 0) {
    if (!(noise.gap_gyro_density > 0) || !std::isfinite(noise.gap_gyro_density))
      throw ConfigError(source, "gap_gyro_density", "must be finite and > 0");
    if (!(noise.gap_accel_density > 0) || !std::isfinite(noise.gap_accel_density))
      throw ConfigError(source, "gap_accel_density", "must be finite and > 0");
  }
}

std::vector<ImuSample> imu_samples_between(const std::vector<ImuSample>& stream, Timestamp t_begin,
                                           Timestamp t_end, std::vector<double>* raw_step_s) {
  if (t_end <= t_begin) {
    throw Error("imu_samples_between: empty interval [" + format_seconds(t_begin) + ", " + format_seconds(t_end) +
                "] s");
  }
  if (stream.empty() || stream.front().t > t_begin || stream.back().t < t_end) {
    throw Error("imu_samples_between: the IMU stream does not cover [" + format_seconds(t_begin) + ", " +
                format_seconds(t_end) + "] s");
  }
  for (std::size_t k = 1; k < stream.size(); ++k) {
    if (stream[k].t <= stream[k - 1].t) {
      throw Error("imu_samples_between: IMU sample times not strictly increasing at index " + std::to_string(k));
    }
  }
  std::vector<ImuSample> out;
  if (raw_step_s) raw_step_s->clear();
  // The step ending at stream[k] (or interpolated just before it) lies in [stream[k-1], stream[k]].
  const auto push = [&](const ImuSample& s, std::size_t k) {
    out.push_back(s);
    if (raw_step_s) raw_step_s->push_back(out.size() == 1 ? 0.0 : ns_to_seconds(stream[k].t - stream[k - 1].t));
  };
  for (std::size_t k = 0; k < stream.size(); ++k) {
    const ImuSample& s = stream[k];
    if (!s.has_gyro) throw Error("imu_samples_between: sample " + std::to_string(k) + " has no gyro data");
    if (s.t < t_begin) {
      if (stream[k + 1].t > t_begin) push(interpolate_sample(s, stream[k + 1], t_begin), k + 1);
      continue;
    }
    if (s.t > t_end) {
      push(interpolate_sample(stream[k - 1], s, t_end), k);
      break;
    }
    push(s, k);
    if (s.t == t_end) break;
  }
  return out;
}

ImuPreintegration::ImuPreintegration(const ImuNoise& noise, const Vec3& b_g, const Vec3& b_a)
    : noise_(noise), b_g_(b_g), b_a_(b_a) {
  validate(noise_);
}

ImuPreintegration ImuPreintegration::between(const std::vector<ImuSample>& stream, Timestamp t_i, Timestamp t_j,
                                              const ImuNoise& noise, const Vec3& b_g, const Vec3& b_a) {
  ImuPreintegration p(noise, b_g, b_a);
  std::vector<double> raw_step_s;
  const std::vector<ImuSample> samples = imu_samples_between(stream, t_i, t_j, &raw_step_s);
  for (std::size_t m = 0; m < samples.size(); ++m) p.add(samples[m], raw_step_s[m]);
  return p;
}

Timestamp ImuPreintegration::start_time() const { return samples_.empty() ? 0 : samples_.front().t; }
Timestamp ImuPreintegration::end_time() const { return samples_.empty() ? 0 : samples_.back().t; }

void ImuPreintegration::add(const ImuSample& sample, double raw_step_s) {
  if (!sample.has_gyro) throw Error("ImuPreintegration::add: sample without gyro data");
  if (!samples_.empty() && sample.t <= samples_.back().t) {
    throw Error("ImuPreintegration::add: sample time " + format_seconds(sample.t) + " s is not after " +
                format_seconds(samples_.back().t) + " s");
  }
  samples_.push_back(sample);
  raw_step_s_.push_back(raw_step_s);
  if (samples_.size() >= 2) integrate_step(samples_[samples_.size() - 2], samples_.back(), raw_step_s);
}

void ImuPreintegration::reset_integration() {
  dt_ = 0;
  gamma_ = Quat::Identity();
  alpha_.setZero();
  beta_.setZero();
  J_.setIdentity();
  P_.setZero();
}

void ImuPreintegration::repropagate(const Vec3& b_g, const Vec3& b_a) {
  b_g_ = b_g;
  b_a_ = b_a;
  reset_integration();
  for (std::size_t k = 1; k < samples_.size(); ++k) integrate_step(samples_[k - 1], samples_[k], raw_step_s_[k]);
}

bool ImuPreintegration::repropagate_if_needed(const Vec3& b_g, const Vec3& b_a, double gyro_threshold,
                                              double accel_threshold) {
  if ((b_g - b_g_).norm() <= gyro_threshold && (b_a - b_a_).norm() <= accel_threshold) return false;
  repropagate(b_g, b_a);
  return true;
}

void ImuPreintegration::integrate_step(const ImuSample& s0, const ImuSample& s1, double raw_step_s) {
  const double h = ns_to_seconds(s1.t - s0.t);
  if (noise_.max_sample_gap_s > 0 && std::max(h, raw_step_s) > noise_.max_sample_gap_s) {
    // Two sub-steps at least (one alone drives position and velocity with the same three force
    // errors), at most 2000: a longer gap gets longer ones and the covariance stays full rank.
    const int n =
        static_cast<int>(std::clamp(std::ceil(h / (0.5 * noise_.max_sample_gap_s)), 2.0, 2000.0));
    ImuSample a = s0;
    for (int k = 1; k <= n; ++k) {
      const auto t = s0.t + static_cast<Timestamp>(std::llround(static_cast<double>(s1.t - s0.t) * k / n));
      const ImuSample b = k == n ? s1 : interpolate_sample(s0, s1, t);
      integrate_substep(a, b, noise_.gap_gyro_density, noise_.gap_accel_density);
      a = b;
    }
    return;
  }
  integrate_substep(s0, s1, noise_.gyro_noise_density, noise_.accel_noise_density);
}

void ImuPreintegration::integrate_substep(const ImuSample& s0, const ImuSample& s1, double ng, double na) {
  const double h = ns_to_seconds(s1.t - s0.t);
  const Mat3 I = Mat3::Identity();

  // Nominal mid-point step.
  const Vec3 w = 0.5 * (s0.gyro + s1.gyro) - b_g_;
  const Vec3 phi = w * h;
  const Quat dq = so3_exp(phi);
  const Mat3 dR = dq.toRotationMatrix();
  const Mat3 R0 = gamma_.toRotationMatrix();
  const Quat gamma1 = (gamma_ * dq).normalized();
  const Mat3 R1 = gamma1.toRotationMatrix();
  const Vec3 u0 = s0.accel - b_a_;
  const Vec3 u1 = s1.accel - b_a_;
  const Vec3 a = 0.5 * (R0 * u0 + R1 * u1);

  // Exact linearization of the step. A rate error e (bias error -db_g or noise) rotates the end
  // orientation by Jr(phi) h e; the mean specific force sees the start and end rotation errors.
  const Mat3 Jr_h = so3_right_jacobian(phi) * h;
  const Mat3 a_theta = -0.5 * (R0 * hat(u0) + R1 * hat(u1) * dR.transpose());
  const Mat3 a_rate = -0.5 * R1 * hat(u1) * Jr_h;  // d a / d e
  const Mat3 a_force = 0.5 * (R0 + R1);             // d a / d (specific-force error)

  Mat15 F = Mat15::Identity();
  F.block<3, 3>(kTheta, kTheta) = dR.transpose();
  F.block<3, 3>(kTheta, kBiasGyro) = -Jr_h;
  F.block<3, 3>(kAlpha, kTheta) = 0.5 * h * h * a_theta;
  F.block<3, 3>(kAlpha, kBeta) = h * I;
  F.block<3, 3>(kAlpha, kBiasGyro) = -0.5 * h * h * a_rate;
  F.block<3, 3>(kAlpha, kBiasAccel) = -0.5 * h * h * a_force;
  F.block<3, 3>(kBeta, kTheta) = h * a_theta;
  F.block<3, 3>(kBeta, kBiasGyro) = -h * a_rate;
  F.block<3, 3>(kBeta, kBiasAccel) = -h * a_force;

  // Noise inputs [rate noise, specific-force noise, gyro bias walk, accel bias walk].
  Eigen::Matrix<double, 15, 12> G = Eigen::Matrix<double, 15, 12>::Zero();
  G.block<3, 3>(kTheta, 0) = Jr_h;
  G.block<3, 3>(kAlpha, 0) = 0.5 * h * h * a_rate;
  G.block<3, 3>(kAlpha, 3) = 0.5 * h * h * a_force;
  G.block<3, 3>(kBeta, 0) = h * a_rate;
  G.block<3, 3>(kBeta, 3) = h * a_force;
  G.block<3, 3>(kBiasGyro, 6) = I;
  G.block<3, 3>(kBiasAccel, 9) = I;
  Eigen::Matrix<double, 12, 1> q;
  const double wg = noise_.gyro_random_walk, wa = noise_.accel_random_walk;
  q << Vec3::Constant(ng * ng / h), Vec3::Constant(na * na / h), Vec3::Constant(wg * wg * h),
      Vec3::Constant(wa * wa * h);

  P_ = F * P_ * F.transpose() + G * q.asDiagonal() * G.transpose();
  // The mid-point sums lose the force noise's spread of position within the step (q_a h^3/12;
  // free fall then gives the continuous-time q_a T^3/3 exactly). Without it an interval of one
  // step (two frames between two IMU samples) has a singular covariance: position and velocity
  // driven by the same three force errors.
  P_.block<3, 3>(kAlpha, kAlpha) += (na * na * h * h * h / 12.0) * I;
  P_ = 0.5 * (P_ + P_.transpose());
  J_ = F * J_;

  alpha_ += beta_ * h + 0.5 * h * h * a;
  beta_ += a * h;
  gamma_ = gamma1;
  dt_ = ns_to_seconds(s1.t - samples_.front().t);  // from integer time: no accumulated rounding
}

Quat ImuPreintegration::corrected_delta_q(const Vec3& b_g) const {
  return (gamma_ * so3_exp(d_theta_d_bg() * (b_g - b_g_))).normalized();
}

Vec3 ImuPreintegration::corrected_delta_p(const Vec3& b_g, const Vec3& b_a) const {
  return alpha_ + d_alpha_d_bg() * (b_g - b_g_) + d_alpha_d_ba() * (b_a - b_a_);
}

Vec3 ImuPreintegration::corrected_delta_v(const Vec3& b_g, const Vec3& b_a) const {
  return beta_ + d_beta_d_bg() * (b_g - b_g_) + d_beta_d_ba() * (b_a - b_a_);
}

void ImuPreintegration::predict(const SE3& T_W_Bi, const Vec3& v_i, const Vec3& b_g, const Vec3& b_a,
                                SE3* T_W_Bj, Vec3* v_j) const {
  const double T = dt_;
  *T_W_Bj = SE3(T_W_Bi.q * corrected_delta_q(b_g),
                T_W_Bi.t + v_i * T + 0.5 * kGravityW * T * T + T_W_Bi.q * corrected_delta_p(b_g, b_a));
  *v_j = v_i + kGravityW * T + T_W_Bi.q * corrected_delta_v(b_g, b_a);
}

}  // namespace navaid::estimation
