// eLabrador's chain (seed elabrador, §III-C/D): the walking route over the streets' OSM map (the
// foot router), cut into 10 m sub-routes; on every estimate the nearest sub-route gives the
// directional subgoal in ENU, the estimate's GPS-map registration T_ENU_W takes it into W, and
// Direction A* on the newest cost map with path following (Alg. 2) says where to walk. While the
// registration is missing or unsure the user is told to wait (PathGuidance's rule). The streets,
// start and destination come with the mission (device_mission.hpp).
#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/runtime/guidance_stage.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "navaid/planning/route_subgoals.hpp"

namespace navaid::runtime {
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
    if (!c.mission.route) throw Error("device " + c.spec.name + " walks a route: the mission needs its streets and destination");
    const RouteMission& m = *c.mission.route;
    const planning::FootRouter router(m.streets, planning::foot_route_config(c.config));
    route_ = router.route(m.from, m.to);
    if (!route_.found())
      throw Error(fmt::format("device {}: no walking route on {} ({}: {})", c.spec.name, m.streets_name,
                              planning::to_string(route_.status), route_.reason));
    const planning::LocalEnu enu(m.origin);
    std::vector<Vec2> points;
    for (const GeoPoint& p : route_.points) points.push_back(enu.to_enu(p));
    subroutes_ = planning::cut_sub_routes(points, sub_.subroute_m);
    if (m.face) face_ENU_ = enu.to_enu(*m.face);
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

}  // namespace navaid::runtime
