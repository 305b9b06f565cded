#include "navaid/simulation/imu_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/time_grid.hpp"

namespace navaid::simulation {

ImuModel::ImuModel(const ImuCalibration& calibration, const ImuModelOptions& options)
    : calib_(calibration),
      options_(options),
      rng_(options.seed),
      b_g_(options.initial_gyro_bias),
      b_a_(options.initial_accel_bias) {
  auto require = [](bool ok, const char* key, const char* what) {
    if (!ok) throw ConfigError("ImuCalibration", key, what);
  };
  require(calib_.rate_hz > 0.0 && std::isfinite(calib_.rate_hz), "rate_hz", "must be > 0");
  require(calib_.gyro_noise_density >= 0.0, "gyro_noise_density", "must be >= 0");
  require(calib_.gyro_random_walk >= 0.0, "gyro_random_walk", "must be >= 0");
  require(calib_.accel_noise_density >= 0.0, "accel_noise_density", "must be >= 0");
  require(calib_.accel_random_walk >= 0.0, "accel_random_walk", "must be >= 0");
  // A scale/misalignment matrix is near the identity; far from it is a unit or sign mistake.
  for (const Mat3* m : {&options_.gyro_scale_misalignment, &options_.accel_scale_misalignment})
    if (!m->allFinite() || (*m - Mat3::Identity()).cwiseAbs().maxCoeff() > 0.2)
      throw ConfigError("ImuModelOptions", m == &options_.gyro_scale_misalignment ? "gyro_scale_misalignment"
                                                                                  : "accel_scale_misalignment",
                        "must be within 0.2 of the identity in every entry (scale errors and misalignments are small)");
}

double ImuModel::gyro_noise_sigma() const { return calib_.gyro_noise_density * std::sqrt(calib_.rate_hz); }
double ImuModel::accel_noise_sigma() const { return calib_.accel_noise_density * std::sqrt(calib_.rate_hz); }

Vec3 ImuModel::gaussian3(double sigma) {
  // Explicit order of draws (x, y, z) keeps streams reproducible across compilers.
  const double x = normal_(rng_);
  const double y = normal_(rng_);
  const double z = normal_(rng_);
  return sigma * Vec3(x, y, z);
}

ImuSample ImuModel::measure(const KinematicState& body, Timestamp t) {
  if (has_last_ && t < last_t_) {
    throw std::invalid_argument("ImuModel::measure: time went backwards (" + std::to_string(t) + " < " +
                                std::to_string(last_t_) + " ns)");
  }
  if (has_last_ && options_.bias_walk && t > last_t_) {
    const double dt = ns_to_seconds(t - last_t_);
    b_g_ += gaussian3(calib_.gyro_random_walk * std::sqrt(dt));
    b_a_ += gaussian3(calib_.accel_random_walk * std::sqrt(dt));
  }
  has_last_ = true;
  last_t_ = t;

  // IMU at lever arm r = t_B_I on the rigid body: a_I = a_B + alpha x r + omega x (omega x r).
  const Mat3 R_W_B = body.T_W_B.rotation();
  const Mat3 R_B_I = calib_.T_B_I.rotation();
  const Vec3& r = calib_.T_B_I.t;
  const Vec3& w = body.omega_B;
  const Vec3 a_W_I = body.a_W + R_W_B * (body.alpha_B.cross(r) + w.cross(w.cross(r)));

  ImuSample s;
  s.t = t;
  s.gyro = options_.gyro_scale_misalignment * (R_B_I.transpose() * w) + b_g_;
  s.accel = options_.accel_scale_misalignment * ((R_W_B * R_B_I).transpose() * (a_W_I - kGravityW)) + b_a_;
  if (options_.white_noise) {
    s.gyro += gaussian3(gyro_noise_sigma());
    s.accel += gaussian3(accel_noise_sigma());
  }
  for (const auto& shock : options_.shocks)
    if (t >= shock.begin && t < shock.end) s.accel += shock.accel_I;
  return s;
}

SimulatedImuStream simulate_imu_stream(const WalkerTrajectory& trajectory, ImuModel& model, double t_begin_s,
                                       double t_end_s, Timestamp epoch) {
  SimulatedImuStream out;
  const std::vector<Timestamp> times = time_grid(t_begin_s, t_end_s, model.calibration().rate_hz);
  out.samples.reserve(times.size());
  out.ground_truth.reserve(times.size());
  for (const Timestamp rel : times) {
    // Integer ns grid first, then the trajectory at exactly those times: no drift between the two.
    const KinematicState st = trajectory.state(ns_to_seconds(rel));
    out.samples.push_back(model.measure(st, epoch + rel));
    GroundTruthState gt;
    gt.t = epoch + rel;
    gt.T_W_B = st.T_W_B;
    gt.v_W = st.v_W;
    gt.b_g = model.gyro_bias();
    gt.b_a = model.accel_bias();
    out.ground_truth.push_back(gt);
  }
  return out;
}

}  // namespace navaid::simulation
