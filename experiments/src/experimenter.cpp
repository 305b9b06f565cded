#include "navaid/experiments/experimenter.hpp"

#include "navaid/experiments/config_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace navaid::experiments {

using Vec2 = Eigen::Vector2d;

namespace {
const ConfigKey<double> kOffRoute{"trial.correction.off_route_m", std::nullopt, {0.0, 1000.0},
                                  "the experimenter corrects a person this far off the route [m]; 0: never; "
                                  "default 5 in route studies, else 0"};
const ConfigKey<double> kStuck{"trial.correction.stuck_s", std::nullopt, {0.0, 36000.0},
                               "the experimenter corrects a person standing this long [s]; 0: never; default 30 in "
                               "route studies, else 0"};
const ConfigKey<double> kAhead{"trial.correction.ahead_m", ExperimenterConfig{}.ahead_m, {0.5, 100.0},
                               "a correction leads the person this far ahead along the route [m]"};
const ConfigKey<double> kCooldown{"trial.correction.cooldown_s", ExperimenterConfig{}.cooldown_s, {0.0, 3600.0},
                                  "least time between two corrections [s]"};
}  // namespace

ConfigSchema experimenter_config_schema() { return ConfigSchema().add(kOffRoute).add(kStuck).add(kAhead).add(kCooldown); }

ExperimenterConfig read_experimenter_config(const Config& config, bool route_study) {
  ExperimenterConfig c;
  c.off_route_m = get(config, defaulting_to(kOffRoute, route_study ? 5.0 : 0.0));
  c.stuck_s = get(config, defaulting_to(kStuck, route_study ? 30.0 : 0.0));
  c.ahead_m = get(config, kAhead);
  c.cooldown_s = get(config, kCooldown);
  return c;
}

Experimenter::Experimenter(const ExperimenterConfig& config, std::vector<Vec2> route)
    : config_(config), route_(std::move(route)) {
  if (route_.size() < 2) throw std::invalid_argument("Experimenter: the route needs at least two points");
  along_.push_back(0.0);
  for (std::size_t i = 1; i < route_.size(); ++i) along_.push_back(along_.back() + (route_[i] - route_[i - 1]).norm());
}

std::optional<double> Experimenter::watch(double t_s, const Vec2& p, double speed_mps, bool arrived) {
  // The nearest point of the route: its distance and its arc length.
  double best = std::numeric_limits<double>::infinity(), best_s = 0;
  for (std::size_t i = 0; i + 1 < route_.size(); ++i) {
    const Vec2 d = route_[i + 1] - route_[i];
    const double len2 = d.squaredNorm();
    const double u = len2 > 0 ? std::clamp((p - route_[i]).dot(d) / len2, 0.0, 1.0) : 0.0;
    const double dist = (route_[i] + u * d - p).norm();
    if (dist < best) {
      best = dist;
      best_s = along_[i] + u * std::sqrt(len2);
    }
  }
  max_off_route_m_ = std::max(max_off_route_m_, best);
  if (arrived) return std::nullopt;
  if (speed_mps > 0.05) standing_since_.reset();
  else if (!standing_since_) standing_since_ = t_s;
  if (last_intervention_ && t_s - *last_intervention_ < config_.cooldown_s) return std::nullopt;
  const bool off = config_.off_route_m > 0 && best > config_.off_route_m;
  const bool stuck = config_.stuck_s > 0 && standing_since_ && t_s - *standing_since_ >= config_.stuck_s;
  if (!off && !stuck) return std::nullopt;
  // Toward the route, ahead_m past the nearest point (its end at most).
  const double s = std::min(best_s + config_.ahead_m, along_.back());
  std::size_t i = 1;
  while (i + 1 < along_.size() && along_[i] < s) ++i;
  const double seg = along_[i] - along_[i - 1];
  const Vec2 target = seg > 0 ? route_[i - 1] + (s - along_[i - 1]) / seg * (route_[i] - route_[i - 1]) : route_[i];
  const Vec2 d = target - p;
  if (d.norm() < 1e-6) return std::nullopt;
  ++corrections_;
  last_intervention_ = t_s;
  standing_since_.reset();
  return std::atan2(d.y(), d.x());
}

}  // namespace navaid::experiments
