#include "navaid/planning/pi_heading_controller.hpp"

#include <algorithm>

#include "navaid/planning/angles.hpp"

namespace navaid::planning {

PiHeadingConfig read_pi_heading_config(const Config& config) {
  PiHeadingConfig c;
  c.kp = config.get_double("planning.pi.kp", c.kp, {0.0, 10.0});
  c.ki = config.get_double("planning.pi.ki", c.ki, {0.0, 10.0});
  c.integral_limit_rad_s = config.get_double("planning.pi.integral_limit_rad_s", c.integral_limit_rad_s, {0.0, 100.0});
  c.output_limit = config.get_double("planning.pi.output_limit", c.output_limit, {1e-6, 100.0});
  c.max_dt_s = config.get_double("planning.pi.max_dt_s", c.max_dt_s, {1e-6, 10.0});
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
