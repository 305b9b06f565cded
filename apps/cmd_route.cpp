// navaid route: an offline walking route on an OpenStreetMap file (docs/routing.md): route.geojson,
// route.png, narration.txt, guidance_timeline.csv (the narration for `navaid cues`) and
// route.json (length, crossings, steps, nodes expanded, time, reason).
// Exit 0 with a route, 4 when there is none (off the graph, unreachable, search limit), 2 on bad input.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/interaction/route_timeline.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/route_narration.hpp"
#include "navaid/planning/route_png.hpp"
#include "navaid/planning/route_subgoals.hpp"

namespace navaid::cli {

namespace {

struct RouteArgs {
  std::filesystem::path osm;
  std::vector<double> from, to;
  std::filesystem::path out;
  std::filesystem::path config_file;
  std::vector<std::string> overrides;
};

planning::GeoPoint point(const std::vector<double>& v, const char* option) {
  if (v.size() != 2) throw UsageError(fmt::format("{} needs LAT,LON (degrees)", option));
  const planning::GeoPoint p{v[0], v[1]};
  if (!planning::valid_lat_lon(p)) {
    throw UsageError(fmt::format("{} {},{}: latitude must be in [-90, 90] and longitude in [-180, 180]", option, v[0], v[1]));
  }
  return p;
}

nlohmann::json crossing_json(const planning::RouteCrossing& c, const planning::Route& r) {
  nlohmann::json j = {{"control", planning::to_string(c.info.control)},
                      {"street", c.street},
                      {"at_m", c.at_m},
                      {"lat", r.points[c.point].lat_deg},
                      {"lon", r.points[c.point].lon_deg},
                      {"island", c.info.island}};
  j["tactile_paving"] = c.info.tactile_paving ? nlohmann::json(*c.info.tactile_paving) : nlohmann::json(nullptr);
  if (!c.info.kerb.empty()) j["kerb"] = c.info.kerb;
  return j;
}

nlohmann::json geojson(const planning::Route& r, const planning::GeoPoint& from, const planning::GeoPoint& to) {
  nlohmann::json features = nlohmann::json::array();
  const auto point_feature = [](const planning::GeoPoint& p, nlohmann::json props) {
    return nlohmann::json{{"type", "Feature"},
                          {"geometry", {{"type", "Point"}, {"coordinates", {p.lon_deg, p.lat_deg}}}},
                          {"properties", std::move(props)}};
  };
  if (r.found()) {
    nlohmann::json line = nlohmann::json::array();
    for (const planning::GeoPoint& p : r.points) line.push_back({p.lon_deg, p.lat_deg});
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "LineString"}, {"coordinates", line}}},
                        {"properties", {{"kind", "route"}, {"length_m", r.length_m}, {"crossings", r.crossings.size()}}}});
    for (const planning::RouteCrossing& c : r.crossings) {
      nlohmann::json props = crossing_json(c, r);
      props["kind"] = "crossing";
      features.push_back(point_feature(r.points[c.point], props));
    }
  }
  features.push_back(point_feature(from, {{"kind", "start"}}));
  features.push_back(point_feature(to, {{"kind", "destination"}}));
  return {{"type", "FeatureCollection"}, {"features", features}};
}

int run(const RouteArgs& a) {
  const planning::GeoPoint from = point(a.from, "--from");
  const planning::GeoPoint to = point(a.to, "--to");
  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", a.overrides)
                                              : Config::load(a.config_file, a.overrides);
  const ConfigReads reads(config);
  const planning::FootRouteConfig route_config = planning::foot_route_config(config);
  const planning::SubRouteConfig sub_config = planning::sub_route_config(config);
  const planning::NarrationConfig narration_config = planning::narration_config(config);
  const interaction::RouteTimelineConfig timeline_config = interaction::read_route_timeline_config(config);
  config.reject_unknown_keys(planning::foot_route_config_schema()
                                 .add(planning::sub_route_config_schema())
                                 .add(planning::narration_config_schema())
                                 .add(interaction::route_timeline_config_schema()));

  const planning::FootGraph graph = planning::load_osm_foot_graph(a.osm);
  const planning::FootRouter router(graph, route_config);
  const planning::Route r = router.route(from, to);
  const std::vector<planning::Instruction> narration = planning::narrate_route(r, graph, narration_config);

  std::filesystem::create_directories(a.out);
  nlohmann::json j;
  j["osm"] = a.osm.string();
  j["from"] = {from.lat_deg, from.lon_deg};
  j["to"] = {to.lat_deg, to.lon_deg};
  j["status"] = planning::to_string(r.status);
  j["reason"] = r.reason;
  j["length_m"] = r.length_m;
  j["cost"] = r.cost;
  j["sidewalk_m"] = r.sidewalk_m;
  j["road_m"] = r.road_m;
  j["steps_m"] = r.steps_m;
  j["steps_segments"] = r.steps_segments;
  j["start_snap_m"] = r.start_snap_m;
  j["goal_snap_m"] = r.goal_snap_m;
  j["nodes_expanded"] = r.expanded;
  j["time_ms"] = 1e3 * r.time_s;
  j["load_time_s"] = graph.stats.load_time_s;
  j["graph"] = {{"osm_nodes", graph.stats.osm_nodes},       {"osm_ways", graph.stats.osm_ways},
                {"walkable_ways", graph.stats.walkable_ways}, {"excluded_ways", graph.stats.excluded_ways},
                {"nodes", graph.nodes.size()},                {"edges", graph.edges.size()},
                {"sidewalk_ways", graph.stats.sidewalk_ways}, {"crossing_ways", graph.stats.crossing_ways},
                {"crossing_nodes", graph.stats.crossing_nodes}, {"steps_ways", graph.stats.steps_ways},
                {"landmarks", graph.landmarks.size()}};
  nlohmann::json crossings = nlohmann::json::array();
  for (const planning::RouteCrossing& c : r.crossings) crossings.push_back(crossing_json(c, r));
  j["crossings"] = crossings;
  nlohmann::json points = nlohmann::json::array();
  for (const planning::GeoPoint& p : r.points) points.push_back({p.lat_deg, p.lon_deg});
  j["points"] = points;
  nlohmann::json lines = nlohmann::json::array();
  for (const planning::Instruction& i : narration) lines.push_back(i.text);
  j["narration"] = lines;
  if (r.found()) {
    // The eLabrador rule at the start: ENU about the start, sub-routes, the first subgoal.
    const planning::LocalEnu enu(GeodeticOrigin{from.lat_deg, from.lon_deg, 0.0});
    std::vector<planning::Vec2> enu_points;
    for (const planning::GeoPoint& p : r.points) enu_points.push_back(enu.to_enu(p));
    const auto subroutes = planning::cut_sub_routes(enu_points, sub_config.subroute_m);
    j["subroutes"] = subroutes.size();
    if (!subroutes.empty()) {
      const planning::RouteSubgoal s = planning::route_subgoal(subroutes, enu.to_enu(from), sub_config.window_m);
      if (s.subgoal.direction_rad) j["first_subgoal_heading_enu_deg"] = *s.subgoal.direction_rad * 180.0 / M_PI;
    }
  }
  std::ofstream(a.out / "route.json") << j.dump(2) << "\n";
  std::ofstream(a.out / "route.geojson") << geojson(r, from, to).dump(1) << "\n";
  {
    std::ofstream text(a.out / "narration.txt");
    if (r.found()) {
      for (const planning::Instruction& i : narration) text << i.text << "\n";
      interaction::write_guidance_timeline_csv(a.out / "guidance_timeline.csv",
                                               interaction::route_timeline(narration, timeline_config));
    } else {
      text << "No route: " << r.reason << "\n";
    }
  }
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());
  const std::string legend =
      r.found() ? fmt::format("{:.0f} m, {} crossings, {:.0f} m of steps, {} nodes", r.length_m, r.crossings.size(),
                              r.steps_m, r.expanded)
                : std::string("no route: ") + planning::to_string(r.status);
  planning::write_route_png(a.out / "route.png", graph, r, from, to, legend);

  std::cout << fmt::format("{}: {} walkable ways, {} nodes, {} edges, loaded in {:.2f} s\n", a.osm.string(),
                           graph.stats.walkable_ways, graph.nodes.size(), graph.edges.size(), graph.stats.load_time_s);
  if (r.found()) {
    std::cout << fmt::format("route: {:.1f} m, {} crossings, {:.0f} m of steps, {} nodes expanded in {:.2f} ms\n",
                             r.length_m, r.crossings.size(), r.steps_m, r.expanded, 1e3 * r.time_s);
    for (const planning::Instruction& i : narration) std::cout << "  " << i.text << "\n";
  } else {
    std::cout << fmt::format("no route ({}): {}\n", planning::to_string(r.status), r.reason);
  }
  std::cout << fmt::format("wrote {}\n", a.out.string());
  return r.found() ? 0 : 4;
}

}  // namespace

void add_route_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("route", "Offline walking route on an OpenStreetMap file (.osm, .osm.gz, .osm.bz2, .osm.pbf)");
  auto a = std::make_shared<RouteArgs>();
  cmd->add_option("--osm", a->osm, "OpenStreetMap file")->required();
  cmd->add_option("--from", a->from, "Start LAT,LON (degrees)")->delimiter(',')->required();
  cmd->add_option("--to", a->to, "Destination LAT,LON (degrees)")->delimiter(',')->required();
  cmd->add_option("--out", a->out, "Output folder (route.json, route.geojson, route.png, narration.txt, guidance_timeline.csv)")->required();
  cmd->add_option("--config", a->config_file, "YAML configuration (planning.route.* keys, docs/routing.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set planning.route.avoid_steps=true (repeatable)");
  cmd->callback([a] {
    const int status = run(*a);
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace navaid::cli
