#include "navaid/planning/pi_heading_controller.hpp"

#include <algorithm>

#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {
const PiHeadingConfig kPiHeadingControllerDefaults;
const ConfigKey<double> kKp{"planning.pi.kp", kPiHeadingControllerDefaults.kp, {0.0, 10.0}, "proportional gain of the PI heading controller"};
const ConfigKey<double> kKi{"planning.pi.ki", kPiHeadingControllerDefaults.ki, {0.0, 10.0}, "integral gain of the PI heading controller"};
const ConfigKey<double> kIntegralLimit{"planning.pi.integral_limit_rad_s", kPiHeadingControllerDefaults.integral_limit_rad_s, {0.0, 100.0},
                                       "bound on the integral of the heading error [rad s]"};
const ConfigKey<double> kOutputLimit{"planning.pi.output_limit", kPiHeadingControllerDefaults.output_limit, {1e-6, 100.0},
                                     "bound on the controller's output"};
const ConfigKey<double> kMaxDt{"planning.pi.max_dt_s", kPiHeadingControllerDefaults.max_dt_s, {1e-6, 10.0},
                               "a longer gap between updates restarts the integral [s]"};
}  // namespace

ConfigSchema pi_heading_config_schema() {
  return ConfigSchema().add(kKp).add(kKi).add(kIntegralLimit).add(kOutputLimit).add(kMaxDt);
}

PiHeadingConfig read_pi_heading_config(const Config& config) {
  PiHeadingConfig c;
  c.kp = get(config, kKp);
  c.ki = get(config, kKi);
  c.integral_limit_rad_s = get(config, kIntegralLimit);
  c.output_limit = get(config, kOutputLimit);
  c.max_dt_s = get(config, kMaxDt);
  return c;
}

double PiHeadingController::update(Timestamp t, double heading_error_rad) {
  const double e = wrap_angle(heading_error_rad);
  if (last_) {
    const double dt = ns_to_seconds(t - *last_);
    if (dt > config_.max_dt_s || dt < 0.0) {
      integral_ = 0.0;
    } else {
      integral_ = std::clamp(integral_ + e * dt, -config_.integral_limit_rad_s, config_.integral_limit_rad_s);
    }
  }
  last_ = t;
  return std::clamp(config_.kp * e + config_.ki * integral_, -config_.output_limit, config_.output_limit);
}

void PiHeadingController::reset() {
  integral_ = 0.0;
  last_.reset();
}

}  // namespace navaid::planning
