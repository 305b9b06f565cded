#include "navaid/simulation/scenario.hpp"

#include <algorithm>
#include <functional>

#include "navaid/core/errors.hpp"
#include "scenarios/families.hpp"

namespace navaid::simulation {

namespace {

using scenarios::Rng;

struct Entry {
  const char* name;
  std::uint64_t seed;
  const char* description;
  std::function<void(Scenario&, Rng&)> build;
};

const std::vector<Entry>& registry() {
  using namespace scenarios;
  static const std::vector<Entry> entries = {
      {"route1", 1, "eLabrador Route 1: residential entrance, ~30 m south, left turn, ~240 m east to a park landmark",
       build_route1},
      {"route2", 2, "eLabrador Route 2: ~300 m straight, two T-junction crosswalks, bus-stop passage, entrance landmark",
       build_route2},
      {"corridor", 3, "Smart Cane guidance test: 10 m x 2 m corridor with a low, a hanging and a standing obstacle",
       build_corridor},
      {"obstacle-course", 4, "BYU augmented cane demonstration: 10 m x 10 m room, dividers, chairs, two hanging obstacles",
       build_obstacle_course},
      {"lab-walk-1", 11, "W-ROMA hand-held walk 1 (short loop around the central tables)",
       [](Scenario& s, Rng& r) { build_lab_walk(s, r, 1); }},
      {"lab-walk-2", 12, "W-ROMA hand-held walk 2 (short figure-eight between the table islands)",
       [](Scenario& s, Rng& r) { build_lab_walk(s, r, 2); }},
      {"lab-walk-3", 13, "W-ROMA hand-held walk 3 (short walk along the shelves and back)",
       [](Scenario& s, Rng& r) { build_lab_walk(s, r, 3); }},
      {"lab-walk-4", 14, "W-ROMA hand-held walk 4 (long: two perimeter laps)",
       [](Scenario& s, Rng& r) { build_lab_walk(s, r, 4); }},
      {"lab-walk-5", 15, "W-ROMA hand-held walk 5 (long: perimeter, corridor and back through the second door)",
       [](Scenario& s, Rng& r) { build_lab_walk(s, r, 5); }},
      {"office1", 101, "Smart Cane planner map office1: 40 x 40 x 4.5 m, rooms off one corridor cross",
       [](Scenario& s, Rng& r) { build_office(s, r, 1); }},
      {"office2", 102, "Smart Cane planner map office2: 40 x 40 x 4.5 m, two parallel corridors and more rooms",
       [](Scenario& s, Rng& r) { build_office(s, r, 2); }},
      {"pillar", 103, "Smart Cane planner map pillar: 40 x 40 x 4.5 m hall with many pillars", build_pillar},
      {"school", 104, "Smart Cane planner map school indoor: 250 x 150 x 5 m, buildings, courtyards, corridors",
       build_school},
  };
  return entries;
}

const Entry& find_entry(std::string_view name) {
  for (const Entry& e : registry())
    if (name == e.name) return e;
  std::string known;
  for (const Entry& e : registry()) known += (known.empty() ? "" : ", ") + std::string(e.name);
  throw ConfigError("", "scenario", "unknown scenario '" + std::string(name) + "'; known scenarios: " + known);
}

}  // namespace

std::vector<std::string> scenario_names() {
  std::vector<std::string> names;
  for (const Entry& e : registry()) names.emplace_back(e.name);
  return names;
}

std::uint64_t default_scenario_seed(std::string_view name) { return find_entry(name).seed; }

Scenario make_scenario(std::string_view name, const ScenarioOptions& options) {
  const Entry& e = find_entry(name);
  Scenario s;
  s.name = e.name;
  s.description = e.description;
  s.seed = options.seed == 0 ? e.seed : options.seed;
  s.place_targets = options.targets;
  s.random_layout = options.random_layout;
  Rng rng(s.seed);
  e.build(s, rng);
  // Moving objects are always generated (so the static world does not depend on the switches),
  // then filtered.
  s.moving.erase(std::remove_if(s.moving.begin(), s.moving.end(),
                                [&](const MovingObject& m) {
                                  return m.kind == MovingKind::kPerson ? !options.people : !options.vehicles;
                                }),
                 s.moving.end());
  return s;
}

World world_at(const Scenario& scenario, double t_s) {
  World w = scenario.world;
  const World moving = moving_world(scenario.moving, t_s);
  for (const Primitive& p : moving.primitives()) w.add(p.shape, p.surface);
  return w;
}

double polyline_length(const std::vector<Vec2>& path) {
  double len = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
  return len;
}

}  // namespace navaid::simulation
