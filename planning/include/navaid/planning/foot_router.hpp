#pragma once
// A* over the foot graph (best_first_search.hpp) between two latitude/longitude points, with costs
// that prefer sidewalks and footways over roads, signalled or tactile-paved crossings over
// uncontrolled or unmarked ones, and (when configured) avoid steps. Costs: docs/routing.md.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/planning/osm_foot_graph.hpp"

namespace navaid::planning {

struct GeoPoint {
  double lat_deg = 0, lon_deg = 0;
};

/// Edge cost = length x factor(way kind) + crossing penalty. Factors >= 1 so that the straight-line
/// distance stays an admissible heuristic.
struct FootRouteConfig {
  double sidewalk_factor = 1.0;           ///< planning.route.sidewalk_factor
  double footway_factor = 1.0;            ///< planning.route.footway_factor (footway, path, pedestrian, ...)
  double crossing_way_factor = 1.0;       ///< planning.route.crossing_way_factor (length of footway=crossing)
  double road_sidewalk_factor = 1.2;      ///< planning.route.road_sidewalk_factor (road with sidewalk=*)
  double road_factor = 2.0;               ///< planning.route.road_factor (road without a sidewalk)
  double steps_factor = 1.5;              ///< planning.route.steps_factor
  bool avoid_steps = false;               ///< planning.route.avoid_steps: steps cost x avoid_steps_factor
  double avoid_steps_factor = 50.0;       ///< planning.route.avoid_steps_factor
  /// Additive penalty per crossing [m], by control; tactile paving multiplies it by tactile_factor.
  double crossing_signals_m = 5.0;        ///< planning.route.crossing_signals_m
  double crossing_marked_m = 15.0;        ///< planning.route.crossing_marked_m (zebra / marked)
  double crossing_uncontrolled_m = 30.0;  ///< planning.route.crossing_uncontrolled_m
  double crossing_unmarked_m = 60.0;      ///< planning.route.crossing_unmarked_m
  double crossing_unknown_m = 30.0;       ///< planning.route.crossing_unknown_m
  double tactile_factor = 0.5;            ///< planning.route.tactile_factor (tactile_paving=yes)
  double max_snap_m = 50.0;               ///< planning.route.max_snap_m: farther from every edge = off-graph
  std::size_t max_expansions = 2'000'000; ///< planning.route.max_expansions
  double max_time_s = 5.0;                ///< planning.route.max_time_s (0 = no wall-clock limit)
};

/// Reads planning.route.* (ConfigError on values out of range).
FootRouteConfig foot_route_config(const Config& config);

enum class RouteStatus { kFound, kOffGraph, kUnreachable, kSearchLimit, kEmptyGraph, kInvalidInput };
const char* to_string(RouteStatus status);

/// A crossing on the route.
struct RouteCrossing {
  std::size_t point = 0;     ///< index into Route::points where it starts
  CrossingInfo info;
  std::string street;        ///< name of the crossed road, when known
  double at_m = 0;           ///< distance along the route
};

struct Route {
  RouteStatus status = RouteStatus::kInvalidInput;
  std::string reason;                    ///< why no route (empty when found)
  std::vector<GeoPoint> points;          ///< snapped start, graph nodes..., snapped goal
  std::vector<std::int64_t> node_ids;    ///< OSM id per point (0 for the snapped ends)
  std::vector<std::uint32_t> segment_way;///< way index per segment points[i] -> points[i+1]
  double length_m = 0, cost = 0;
  std::vector<RouteCrossing> crossings;
  std::size_t steps_segments = 0;
  double steps_m = 0, sidewalk_m = 0, road_m = 0;
  double start_snap_m = 0, goal_snap_m = 0;  ///< distance of the inputs to the graph
  std::size_t expanded = 0;
  double time_s = 0;
  bool found() const { return status == RouteStatus::kFound; }
};

/// Where a point meets the graph: edge, fraction t along a->b and the distance to it.
struct EdgeSnap {
  std::uint32_t edge = 0;
  double t = 0, distance_m = 0;
  GeoPoint point;
};

class FootRouter {
 public:
  explicit FootRouter(const FootGraph& graph, FootRouteConfig config = {});

  /// The nearest edge to p (nullopt on an empty graph, or when no edge lies in `component`).
  std::optional<EdgeSnap> snap(const GeoPoint& p, std::optional<std::uint32_t> component = std::nullopt) const;
  /// Connected component of a node (components are numbered by the router).
  std::uint32_t component(std::uint32_t node) const { return component_[node]; }
  /// Cost of traversing edge e fully.
  double edge_cost(std::uint32_t e) const { return edge_cost_[e]; }
  /// When the nearest edges of the two points lie in different connected components (an isolated
  /// courtyard footway next to the street network), the point whose re-snap into the other's
  /// component costs the smaller extra distance is moved there, if that stays within max_snap_m.
  Route route(const GeoPoint& from, const GeoPoint& to) const;

  const FootGraph& graph() const { return graph_; }
  const FootRouteConfig& config() const { return config_; }

 private:
  const FootGraph& graph_;
  FootRouteConfig config_;
  std::vector<double> edge_cost_;
  std::vector<std::uint32_t> component_;
};

/// True when the latitude is in [-90, 90] and the longitude in [-180, 180] (and both finite).
bool valid_lat_lon(const GeoPoint& p);

}  // namespace navaid::planning
