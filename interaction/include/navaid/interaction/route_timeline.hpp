#pragma once
// A narrated route as a guidance timeline for a user walking it at a steady speed: each turn,
// crossing and steps is announced `announce_m` before it ("In 15 meters, turn left onto
// Fasanerieallee."), and arrival is felt and said at the end. `navaid route` writes it, so real
// OpenStreetMap routes can be heard through `navaid cues` before a full-device run walks them.
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/planning/route_narration.hpp"

namespace navaid::interaction {

struct RouteTimelineConfig {
  /// Walking speed [m/s]: about what blind pedestrians with a cane or dog walk (ours).
  double walk_speed_mps = 1.0;
  /// How far ahead of a turn, crossing or steps it is announced [m] (ours).
  double announce_m = 15.0;
};

/// Keys interaction.route.walk_speed_mps [0.2, 3] and interaction.route.announce_m [0, 200].
RouteTimelineConfig read_route_timeline_config(const Config& config);

/// initialized at t = 0, then a route_instruction event per turn, crossing and steps (at the
/// time the walker is announce_m before it, or at 0 when that is behind the start, with the
/// distance left rounded to the metre), and an arrived command at the route's end. Times in
/// seconds from the start. Throws std::invalid_argument for a speed that is not positive.
std::vector<GuidanceTimelineEntry> route_timeline(const std::vector<planning::Instruction>& narration,
                                                  const RouteTimelineConfig& config = {});

}  // namespace navaid::interaction
