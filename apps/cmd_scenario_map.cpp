// navaid scenario-map: a scenario's ground-truth maps for planners and figures: voxel list, 2D
// occupancy (ROS map_server PGM + YAML) of the body's height band, and the top view; with --osm the
// street scenarios' walkways, crossings and landmarks as OpenStreetMap XML plus the route's truth.
#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/simulation/occupancy_export.hpp"
#include "navaid/simulation/osm_export.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/top_view.hpp"

namespace navaid::cli {

namespace {

struct ScenarioMapArgs {
  std::string scenario;
  std::filesystem::path out;
  double resolution = 0.1;
  long long seed = 0;
  std::vector<double> band = {0.2, 2.0};
  bool people = false;
  bool osm = false;
};

void run_osm(const simulation::Scenario& s, const std::filesystem::path& out) {
  const simulation::OsmExport e = simulation::export_osm(s);
  simulation::write_osm_export(e, out);
  std::size_t footways = 0;
  for (const auto& w : e.ways)
    for (const auto& [k, v] : w.tags)
      if (k == "highway" && v == "footway") ++footways;
  const auto& t = e.truth;
  std::cout << fmt::format(
      "{} (seed {}): {} nodes, {} ways ({} footways) around {:.7f}, {:.7f}\n"
      "route: {:.1f} m along the walkways (path {:.1f} m), {} crossing(s), to \"{}\"\n"
      "wrote {}, {}\n",
      s.name, s.seed, e.nodes.size(), e.ways.size(), footways, s.origin.latitude_deg, s.origin.longitude_deg,
      t.length_m, simulation::polyline_length(s.path), t.crossings.size(), t.landmark_name,
      (out / "map.osm").string(), (out / "osm_truth.json").string());
}

void run(const ScenarioMapArgs& a) {
  simulation::ScenarioOptions options;
  options.seed = static_cast<std::uint64_t>(a.seed);
  options.people = options.vehicles = a.people;
  const simulation::Scenario s = simulation::make_scenario(a.scenario, options);
  if (a.osm) {
    if (!simulation::has_streets(s.name))
      throw UsageError("scenario " + s.name + " has no streets to export (--osm works on route1 and route2)");
    run_osm(s, a.out);
    return;
  }
  if (a.band.size() != 2 || !(a.band[1] > a.band[0]))
    throw UsageError("--band needs two heights above the ground, low < high (e.g. --band 0.2 2.0)");
  std::filesystem::create_directories(a.out);
  const std::string stem = (a.out / s.name).string();

  const simulation::World world = a.people ? simulation::world_at(s, 0.0) : s.world;
  const simulation::OccupancyGrid3D grid = simulation::voxelize(world, a.resolution, world.bounds());  // walls may lie just outside the documented extent
  simulation::write_voxel_csv(grid, stem + "-voxels.csv");
  simulation::write_occupancy_map(grid, s.ground_z_m + a.band[0], s.ground_z_m + a.band[1], stem + "-occupancy");
  const simulation::RayCaster caster(world);
  io::write_png(stem + "-topview.png", simulation::render_top_view(caster, simulation::scenario_map_options(s, 1200.0)).image, 6);
  std::cout << fmt::format(
      "{} (seed {}): {:.1f} x {:.1f} x {:.1f} m, path {:.1f} m; {} x {} x {} voxels of {} m over the world's bounds, {} occupied\n"
      "wrote {}-voxels.csv, {}-occupancy.pgm/.yaml (band {}..{} m above ground), {}-topview.png\n",
      s.name, s.seed, s.extent.max.x() - s.extent.min.x(), s.extent.max.y() - s.extent.min.y(),
      s.extent.max.z() - s.extent.min.z(), simulation::polyline_length(s.path), grid.size.x(), grid.size.y(),
      grid.size.z(), a.resolution, grid.count_occupied(), stem, stem, a.band[0], a.band[1], stem);
}

}  // namespace

void add_scenario_map_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("scenario-map",
                                 "Export a scenario's ground-truth maps: voxels (CSV), 2D occupancy (ROS map_server "
                                 "PGM + YAML) and top view (PNG); --osm: the streets as OpenStreetMap XML");
  auto a = std::make_shared<ScenarioMapArgs>();
  cmd->add_option("--scenario", a->scenario, "Scenario name (navaid simulate --list)")->required();
  cmd->add_option("--out", a->out, "Output folder")->required();
  cmd->add_option("--resolution", a->resolution, "Voxel size [m] (default 0.1)")->check(CLI::Range(0.01, 5.0));
  cmd->add_option("--seed", a->seed, "World seed (default: the scenario's documented seed)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--band", a->band, "Heights above ground [m] of the 2D occupancy slice (default 0.2 2.0)")->expected(2);
  cmd->add_flag("--moving", a->people, "Include people and vehicles at their start positions (default: static world)");
  cmd->add_flag("--osm", a->osm,
                "Street scenarios (route1, route2): write only map.osm (OSM XML 0.6 of the walkways, crossings, roads "
                "and landmarks in the scenario's geodetic frame) and osm_truth.json (the scenario's route)");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
