#pragma once
// Turn-by-turn text for a foot route: turns (slight / plain / sharp, left or right, with the
// distance since the previous instruction and the street), crossings (control, tactile paving, kerb,
// island and the street crossed), steps, and the destination with the nearest landmark and its side
// ("the destination is Café X, on your left"). Rules: docs/routing.md.
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/planning/foot_router.hpp"

namespace navaid::planning {

struct NarrationConfig {
  double straight_deg = 20.0;     ///< planning.route.narration.straight_deg: smaller heading changes are not turns
  double slight_deg = 45.0;       ///< planning.route.narration.slight_deg: up to this a turn is "slight"
  double sharp_deg = 135.0;       ///< planning.route.narration.sharp_deg: beyond this a turn is "sharp"
  double turn_window_m = 5.0;     ///< planning.route.narration.turn_window_m: headings over this arc before/after a vertex
  double landmark_radius_m = 40.0;///< planning.route.narration.landmark_radius_m: landmarks this close to the destination
};
NarrationConfig narration_config(const Config& config);

enum class InstructionKind { kStart, kTurn, kCrossing, kSteps, kArrive };

struct Instruction {
  InstructionKind kind = InstructionKind::kStart;
  double at_m = 0;      ///< along the route
  double turn_deg = 0;  ///< kTurn: heading change, positive = left
  /// kTurn: the way turned onto when its name changes there; kCrossing: the street crossed
  /// (empty when unnamed).
  std::string road;
  std::string text;
};

std::vector<Instruction> narrate_route(const Route& route, const FootGraph& graph, const NarrationConfig& config = {});

}  // namespace navaid::planning
