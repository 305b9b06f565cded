#pragma once
// Builders of the scenario families (one source file each); the registry in scenario.cpp names
// them. Each fills world, path, origin, moving objects, extent, mount and deliberate obstacles.
#include "navaid/simulation/scenario.hpp"
#include "scenarios/builders.hpp"

namespace navaid::simulation::scenarios {

void build_route1(Scenario& s, Rng& rng);       // elabrador_routes.cpp
void build_route2(Scenario& s, Rng& rng);       // elabrador_routes.cpp
void build_corridor(Scenario& s, Rng& rng);     // cane_rooms.cpp
void build_obstacle_course(Scenario& s, Rng& rng);  // cane_rooms.cpp
void build_lab_walk(Scenario& s, Rng& rng, int index);  // lab_walks.cpp, index 1..5
void build_office(Scenario& s, Rng& rng, int variant);  // planner_maps.cpp, variant 1 or 2
void build_pillar(Scenario& s, Rng& rng);       // planner_maps.cpp
void build_school(Scenario& s, Rng& rng);       // planner_maps.cpp

}  // namespace navaid::simulation::scenarios
