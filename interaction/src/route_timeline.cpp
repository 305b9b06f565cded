#include "navaid/interaction/route_timeline.hpp"

#include "navaid/interaction/config_schema.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace navaid::interaction {

namespace {
const ConfigKey<double> kWalkSpeed{"interaction.route.walk_speed_mps", RouteTimelineConfig{}.walk_speed_mps, {0.2, 3.0},
                                   "walking speed of a route's cue timeline [m/s]"};
const ConfigKey<double> kAnnounce{"interaction.route.announce_m", RouteTimelineConfig{}.announce_m, {0.0, 200.0},
                                  "a turn, crossing or steps is announced this far ahead [m]"};
}  // namespace

ConfigSchema route_timeline_config_schema() { return ConfigSchema().add(kWalkSpeed).add(kAnnounce); }

RouteTimelineConfig read_route_timeline_config(const Config& config) {
  RouteTimelineConfig c;
  c.walk_speed_mps = get(config, kWalkSpeed);
  c.announce_m = get(config, kAnnounce);
  return c;
}

std::vector<GuidanceTimelineEntry> route_timeline(const std::vector<planning::Instruction>& narration,
                                                  const RouteTimelineConfig& config) {
  if (!(config.walk_speed_mps > 0.0)) throw std::invalid_argument("route_timeline: walking speed must be positive");
  const double v = config.walk_speed_mps;
  std::vector<GuidanceTimelineEntry> out;
  out.emplace_back(SystemEvent{0, SystemEventKind::kInitialized, {}});
  std::vector<std::pair<Timestamp, SystemEvent>> announcements;
  for (const planning::Instruction& i : narration) {
    std::string what;
    switch (i.kind) {
      case planning::InstructionKind::kTurn: what = i.turn_deg > 0.0 ? "left" : "right"; break;
      case planning::InstructionKind::kCrossing: what = "cross"; break;
      case planning::InstructionKind::kSteps: what = "steps"; break;
      case planning::InstructionKind::kStart:
      case planning::InstructionKind::kArrive: continue;
    }
    const double at_s = std::max(0.0, (i.at_m - config.announce_m) / v);
    const double left_m = std::max(0.0, i.at_m - v * at_s);
    std::string value = fmt::format("{:.0f};{}", left_m, what);
    if (what != "steps" && !i.road.empty()) value += ";" + i.road;
    const Timestamp t = seconds_to_ns(at_s);
    announcements.emplace_back(t, SystemEvent{t, SystemEventKind::kRouteInstruction, value});
  }
  // Announcement times follow the route order except where several fall before the start.
  std::stable_sort(announcements.begin(), announcements.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (auto& [t, e] : announcements) out.emplace_back(std::move(e));
  const auto arrive = std::find_if(narration.begin(), narration.end(),
                                   [](const planning::Instruction& i) { return i.kind == planning::InstructionKind::kArrive; });
  if (arrive != narration.end()) {
    planning::GuidanceCommand c;
    c.t = std::max(seconds_to_ns(arrive->at_m / v), entry_time(out.back()));
    c.action = planning::GuidanceAction::kArrived;
    c.reason = planning::GuidanceReason::kPathFound;
    c.confidence = 1.0;
    out.emplace_back(c);
  }
  return out;
}

}  // namespace navaid::interaction
