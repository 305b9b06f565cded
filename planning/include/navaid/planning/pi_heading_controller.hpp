#pragma once
// The Smart Cane's kinesthetic-feedback track controller (seed smart-cane-biped-walking-path-
// generation, §III-D, eq. 1): a PI controller on the heading error,
//     v = K_p (theta_ref - theta) + K_i integral_0^t (theta_ref - theta) dtau,
// whose non-dimensional output drives the steering motor of the cane (GuidanceCommand's
// steering_rad). The paper tunes 0.3 <= K_p <= 0.5 and 0.02 <= K_i <= 0.04 per user; we default to
// the middle of both ranges. The error is wrapped into (-pi, pi] (a reference across the +-180
// seam is a small turn, not a full circle), the integral is clamped (anti-windup: a user who stops
// in front of an obstacle must not build up a violent pull), and so is the output (the motor's
// range).
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"

namespace navaid::planning {

struct PiHeadingConfig {
  double kp = 0.4;
  double ki = 0.03;
  double integral_limit_rad_s = 3.0;  ///< |integral of the error| <= this [rad s]
  double output_limit = 1.0;          ///< |v| <= this
  double max_dt_s = 0.5;              ///< a longer gap between updates restarts the integral
};

/// Keys planning.pi.kp in [0, 10], .ki in [0, 10], .integral_limit_rad_s in [0, 100],
/// .output_limit in (0, 100], .max_dt_s in (0, 10].
PiHeadingConfig read_pi_heading_config(const Config& config);

class PiHeadingController {
 public:
  explicit PiHeadingController(const PiHeadingConfig& config = {}) : config_(config) {}

  /// One control step at time t with the heading error theta_ref - theta [rad] (wrapped here).
  /// The integral uses the rectangle rule over the time since the last update.
  double update(Timestamp t, double heading_error_rad);
  void reset();
  double integral() const { return integral_; }

 private:
  PiHeadingConfig config_;
  double integral_ = 0.0;
  std::optional<Timestamp> last_;
};

}  // namespace navaid::planning
