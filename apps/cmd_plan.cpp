// navaid plan: one local planner on one map, from a start pose to a goal point or direction;
// writes plan.json (path, cost, nodes expanded, time, reason) and plan.png.
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command_schemas.hpp"
#include "commands.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/local_planner.hpp"
#include "navaid/planning/plan_png.hpp"
#include "plan_map.hpp"

namespace navaid::cli {

namespace {

using mapping::Vec2;

struct PlanArgs {
  std::string map;
  std::string planner = "astar";
  std::vector<double> start;
  std::vector<double> goal;
  std::optional<double> direction_deg;
  double sigma_xy = 0.0;
  std::filesystem::path out;
  std::filesystem::path config_file;
  std::vector<std::string> overrides;
};

nlohmann::json plan_json(const planning::Plan& p) {
  nlohmann::json path = nlohmann::json::array();
  for (std::size_t i = 0; i < p.path_W.size(); ++i) {
    nlohmann::json q = {p.path_W[i].x(), p.path_W[i].y()};
    if (i < p.yaw_rad.size()) q.push_back(planning::rad_to_deg(p.yaw_rad[i]));
    path.push_back(q);
  }
  nlohmann::json footsteps = nlohmann::json::array();
  for (const Vec2& f : p.footsteps_W) footsteps.push_back({f.x(), f.y()});
  return {{"status", p.found() ? "found" : "not-found"},
          {"reason", std::string(planning::to_string(p.reason))},
          {"detail", p.detail},
          {"length_m", p.length_m},
          {"cost", p.found() ? nlohmann::json(p.cost) : nlohmann::json(nullptr)},
          {"nodes_expanded", p.expanded},
          {"time_ms", 1e3 * p.time_s},
          {"path", path},
          {"footsteps", footsteps}};
}

int run(const PlanArgs& a) {
  if (a.start.size() != 3) throw UsageError("--start needs X,Y,YAW (metres, metres, degrees)");
  if (!a.goal.empty() && a.goal.size() != 2) throw UsageError("--goal needs X,Y (metres)");
  if (a.goal.empty() == !a.direction_deg.has_value()) {
    throw UsageError("give exactly one of --goal X,Y and --direction DEG");
  }
  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", a.overrides)
                                              : Config::load(a.config_file, a.overrides);
  const ConfigReads reads(config);
  const std::unique_ptr<planning::LocalPlanner> planner = planning::make_local_planner(a.planner, config);
  const PlanMap map = load_plan_map(a.map, config);
  config.reject_unknown_keys(planning::local_planner_schema(a.planner).add(plan_map_schema()));

  mapping::Esdf2d esdf;
  esdf.update(map.cost);
  planning::PlanningProblem problem;
  problem.cost = &map.cost;
  problem.esdf = &esdf;
  problem.start = planning::PlanarPose{Vec2(a.start[0], a.start[1]), planning::deg_to_rad(a.start[2])};
  if (!a.goal.empty()) problem.goal_W = Vec2(a.goal[0], a.goal[1]);
  if (a.direction_deg) problem.goal_direction_rad = planning::deg_to_rad(*a.direction_deg);
  problem.sigma_xy_m = a.sigma_xy;
  const planning::Plan plan = planner->plan(problem);

  std::filesystem::create_directories(a.out);
  nlohmann::json j = plan_json(plan);
  j["planner"] = std::string(planner->name());
  j["map"] = map.description;
  j["start"] = a.start;
  if (problem.goal_W) j["goal"] = a.goal;
  if (a.direction_deg) j["direction_deg"] = *a.direction_deg;
  j["sigma_xy_m"] = a.sigma_xy;
  std::ofstream(a.out / "plan.json") << j.dump(2) << "\n";
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());
  planning::write_plan_png(a.out / "plan.png", map.cost, problem, {{std::string(planner->name()), &plan}});
  std::cout << map.description << "\n";
  if (plan.found()) {
    std::cout << fmt::format("{}: path of {:.2f} m ({} points), cost {:.3f}, {} nodes expanded in {:.2f} ms\n",
                             planner->name(), plan.length_m, plan.path_W.size(), plan.cost, plan.expanded,
                             1e3 * plan.time_s);
  } else {
    std::cout << fmt::format("{}: no path ({}): {}\n", planner->name(), planning::to_string(plan.reason), plan.detail);
  }
  std::cout << fmt::format("wrote {}, {}\n", (a.out / "plan.json").string(), (a.out / "plan.png").string());
  return plan.found() ? 0 : 4;  // 4: the map has no path (2 is an error, 3 an internal one)
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plan", "Plan a path on a map with a local planner (A*, Direction A*, WPG)");
  auto a = std::make_shared<PlanArgs>();
  cmd->add_option("--map", a->map,
                  "scenario:NAME, a map_server .yaml, an OctoMap .bt/.ot, or a folder (navaid map output or one .yaml)")
      ->required();
  cmd->add_option("--planner", a->planner, "astar | direction-astar | wpg (default astar)");
  cmd->add_option("--start", a->start, "Start X,Y,YAW in the map frame (m, m, degrees)")->delimiter(',')->required();
  cmd->add_option("--goal", a->goal, "Goal X,Y (m)")->delimiter(',');
  cmd->add_option("--direction", a->direction_deg, "Directional subgoal: heading in the map frame (degrees, 0 = +x)");
  cmd->add_option("--sigma-xy", a->sigma_xy, "Horizontal position sigma of the start [m]: clearance grows with it")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--out", a->out, "Output folder (plan.json, plan.png, config.yaml)")->required();
  cmd->add_option("--config", a->config_file, "YAML configuration (planning.* keys, docs/planning.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set planning.direction_astar.beta=2 (repeatable)");
  cmd->callback([a] {
    const int status = run(*a);
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace navaid::cli
