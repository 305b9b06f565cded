#pragma once
// The experimenter who walks beside a trial's participant (eLabrador §V-E, "correction number":
// the times the participant had to be intervened to change their current action, a wrong way or a
// blocked path). Here they intervene when the person is further than off_route_m from the route
// or has stood for stuck_s without having arrived: they turn the person toward the route,
// ahead_m past their nearest point on it, and let them walk on. After an intervention they wait
// cooldown_s before the next, as a person walking back to the route needs a moment.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/config.hpp"

namespace navaid::experiments {

struct ExperimenterConfig {
  double off_route_m = 0;  ///< 0: never for leaving the route
  double stuck_s = 0;      ///< 0: never for standing
  double ahead_m = 5.0;
  double cooldown_s = 10.0;
};

/// Keys trial.correction.off_route_m, stuck_s, ahead_m, cooldown_s. `route_study`: the defaults of
/// a route trial (5 m, 30 s), else 0 (no experimenter).
ExperimenterConfig read_experimenter_config(const Config& config, bool route_study);

class Experimenter {
 public:
  /// `route`: the walk as the experimenter knows it (>= 2 points, in W).
  Experimenter(const ExperimenterConfig& config, std::vector<Eigen::Vector2d> route);

  /// Watches the person at time t; the heading in W they are turned to when the experimenter
  /// intervenes now.
  std::optional<double> watch(double t_s, const Eigen::Vector2d& position, double speed_mps, bool arrived);

  std::size_t corrections() const { return corrections_; }
  /// Distance from the route now [m], and the largest so far.
  double max_off_route_m() const { return max_off_route_m_; }

 private:
  ExperimenterConfig config_;
  std::vector<Eigen::Vector2d> route_;
  std::vector<double> along_;  ///< arc length at each route point
  std::optional<double> standing_since_;
  std::optional<double> last_intervention_;
  std::size_t corrections_ = 0;
  double max_off_route_m_ = 0;
};

}  // namespace navaid::experiments
