#pragma once
// A simple grid A* on a world's body-band occupancy, used to give planner maps a walkable
// start-goal polyline (private to the simulation room).
#include <optional>
#include <vector>

#include "navaid/simulation/scenario.hpp"

namespace navaid::simulation::scenarios {

/// Shortest 8-connected path over cells whose centre keeps `clearance_m` (plus discretization
/// margin) from voxels occupied in the clearance band, inside the rectangle [lo, hi]; shortcut
/// by line of sight. nullopt when start or goal is blocked or no path exists.
std::optional<std::vector<Vec2>> plan_grid_path(const World& world, const Vec2& lo, const Vec2& hi, double resolution_m,
                                                const Vec2& start, const Vec2& goal, double clearance_m);

}  // namespace navaid::simulation::scenarios
