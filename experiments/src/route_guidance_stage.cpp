// eLabrador's chain (seed elabrador, §III-C/D): the walking route over the streets' OSM map (the
// foot router), cut into 10 m sub-routes; on every estimate the nearest sub-route gives the
// directional subgoal in ENU, the estimate's GPS-map registration T_ENU_W takes it into W, and
// Direction A* on the newest cost map with path following (Alg. 2) says where to walk. While the
// registration is missing or unsure the user is told to wait (PathGuidance's rule).
#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/experiments/guidance_stage.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "navaid/planning/route_subgoals.hpp"
#include "navaid/simulation/osm_export.hpp"

namespace navaid::experiments {
namespace {

using mapping::Vec2;

using planning::GeoPoint;

const ConfigKey<std::string> kPlanner{"planning.planner", std::string("direction-astar"), {"direction-astar", "astar"},
                                      "route guidance: the local planner toward each sub-route's subgoal"};

class RouteGuidanceStage final : public GuidanceStage {
 public:
  explicit RouteGuidanceStage(const GuidanceStageContext& c)
      : sub_(planning::sub_route_config(c.config)),
        guidance_(planning::read_path_guidance_config(c.config),
                  planning::make_local_planner(get(c.config, kPlanner), c.config)),
        planner_name_(get(c.config, kPlanner)) {
    const planning::FootRouteConfig route_config = planning::foot_route_config(c.config);
    if (!c.recording.origin)
      throw Error(c.recording_dir.string() + ": no geodetic origin; device " + c.spec.name +
                  " maps its route into the estimator's ENU frame at the recording's origin");
    std::filesystem::path osm = c.spec.route_osm;
    std::optional<GeoPoint> from, to, face;
    if (c.spec.route_to) to = GeoPoint{c.spec.route_to->first, c.spec.route_to->second};
    if (c.spec.route_face) face = GeoPoint{c.spec.route_face->first, c.spec.route_face->second};
    if (osm.empty()) {
      // A simulated recording: its scenario's streets as OSM, and its path's ends.
      const auto scenario = recording_scenario(c.recording_dir);
      if (!scenario) throw Error(c.recording_dir.string() + ": not a simulated recording; set device.route.osm");
      const simulation::OsmExport e = simulation::export_osm(*scenario);
      simulation::write_osm_export(e, c.out / "route");
      osm = c.out / "route" / "map.osm";
      from = GeoPoint{e.truth.start_lat_deg, e.truth.start_lon_deg};
      if (!to) to = GeoPoint{e.truth.goal_lat_deg, e.truth.goal_lon_deg};
      if (!face && !e.truth.landmark_name.empty()) face = GeoPoint{e.truth.landmark_lat_deg, e.truth.landmark_lon_deg};
    } else if (!c.recording.gps.empty()) {
      from = GeoPoint{c.recording.gps.front().latitude_deg, c.recording.gps.front().longitude_deg};
    }
    if (!from || !to) throw Error("device " + c.spec.name + ": the route needs a start (GPS) and device.route.to");
    graph_ = planning::load_osm_foot_graph(osm);
    const planning::FootRouter router(graph_, route_config);
    route_ = router.route(*from, *to);
    if (!route_.found())
      throw Error(fmt::format("device {}: no walking route on {} ({}: {})", c.spec.name, osm.string(),
                              planning::to_string(route_.status), route_.reason));
    const planning::LocalEnu enu(*c.recording.origin);
    std::vector<Vec2> points;
    for (const GeoPoint& p : route_.points) points.push_back(enu.to_enu(p));
    subroutes_ = planning::cut_sub_routes(points, sub_.subroute_m);
    if (face) face_ENU_ = enu.to_enu(*face);
    if (subroutes_.empty()) throw Error("device " + c.spec.name + ": the route has no length");
  }

  GuidanceOutput update(const GuidanceInput& in) override {
    GuidanceOutput out;
    out.planner = planner_name_;
    const StateEstimate& e = in.estimate;
    planning::Subgoal subgoal;
    subgoal.from_route = true;  // without a registration PathGuidance withholds the direction
    if (e.T_ENU_W) {
      const Vec2 user_ENU = (*e.T_ENU_W * e.T_W_B.t).head<2>();
      planning::RouteSubgoal rs = planning::route_subgoal(subroutes_, user_ENU, sub_.window_m);
      if (rs.reaches_destination) rs.subgoal.face_W = face_ENU_;  // turned to face it on arrival
      subgoal = planning::subgoal_in_world(rs.subgoal, *e.T_ENU_W);
      last_subroute_ = rs.subroute;
      max_distance_to_route_m_ = std::max(max_distance_to_route_m_, rs.distance_to_route_m);
    }
    if (!in.maps) {
      out.command = waiting_command(e.t, planning::GuidanceReason::kLocating, "no local map yet");
      return out;
    }
    const std::size_t plans_before = guidance_.stats().plans;
    out.command = guidance_.update(e, in.maps->cost, &in.maps->esdf, subgoal);
    if (guidance_.stats().plans > plans_before && guidance_.plan()) out.new_plan = *guidance_.plan();
    return out;
  }

  nlohmann::ordered_json summary() const override {
    const auto& s = guidance_.stats();
    return {{"route_length_m", route_.length_m},
            {"route_points", route_.points.size()},
            {"subroutes", subroutes_.size()},
            {"faces_landmark", face_ENU_.has_value()},
            {"last_subroute", last_subroute_},
            {"max_distance_to_route_m", max_distance_to_route_m_},
            {"planner", planner_name_},
            {"updates", s.updates},
            {"plans", s.plans},
            {"plans_failed", s.plans_failed},
            {"withheld", s.locating},
            {"blocked", s.blocked}};
  }

 private:
  planning::SubRouteConfig sub_;
  planning::PathGuidance guidance_;
  std::string planner_name_;
  planning::FootGraph graph_;
  planning::Route route_;
  std::vector<planning::SubRoute> subroutes_;
  std::optional<Vec2> face_ENU_;  ///< the destination's landmark
  std::size_t last_subroute_ = 0;
  double max_distance_to_route_m_ = 0;
};

}  // namespace

ConfigSchema route_guidance_stage_schema() {
  return ConfigSchema()
      .add(planning::sub_route_config_schema())
      .add(planning::path_guidance_config_schema())
      .add(kPlanner)
      .add(planning::local_planner_schema("direction-astar"))
      .add(planning::local_planner_schema("astar"))
      .add(planning::foot_route_config_schema());
}

std::unique_ptr<GuidanceStage> make_route_guidance_stage(const GuidanceStageContext& context) {
  return std::make_unique<RouteGuidanceStage>(context);
}

}  // namespace navaid::experiments
