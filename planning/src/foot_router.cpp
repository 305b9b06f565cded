#include "navaid/planning/foot_router.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "navaid/planning/best_first_search.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {

constexpr double kFootRouterDeg = 3.14159265358979323846 / 180.0;
constexpr double kRadius = 6371008.8;
constexpr double kInf = std::numeric_limits<double>::infinity();

double crossing_penalty(const FootRouteConfig& c, const CrossingInfo& x) {
  double p = 0;
  switch (x.control) {
    case CrossingControl::kNone: return 0;
    case CrossingControl::kTrafficSignals: p = c.crossing_signals_m; break;
    case CrossingControl::kMarked: p = c.crossing_marked_m; break;
    case CrossingControl::kUncontrolled: p = c.crossing_uncontrolled_m; break;
    case CrossingControl::kUnmarked: p = c.crossing_unmarked_m; break;
    case CrossingControl::kUnknown: p = c.crossing_unknown_m; break;
  }
  return x.tactile_paving.value_or(false) ? p * c.tactile_factor : p;
}

double way_factor(const FootRouteConfig& c, FootWayKind kind) {
  switch (kind) {
    case FootWayKind::kSidewalk: return c.sidewalk_factor;
    case FootWayKind::kCrossing: return c.crossing_way_factor;
    case FootWayKind::kFootway: return c.footway_factor;
    case FootWayKind::kSteps: return c.avoid_steps ? c.steps_factor * c.avoid_steps_factor : c.steps_factor;
    case FootWayKind::kRoadWithSidewalk: return c.road_sidewalk_factor;
    case FootWayKind::kRoad: return c.road_factor;
  }
  return 1.0;
}

/// The search space: graph nodes 0..N-1 plus the virtual start N on the start edge.
class FootSpace {
 public:
  using State = std::uint32_t;
  static constexpr bool kDenseKeys = true;

  FootSpace(const FootGraph& g, const std::vector<double>& cost, const EdgeSnap& start, const EdgeSnap& goal,
            double min_factor)
      : g_(g), cost_(cost), start_(start), goal_(goal), min_factor_(min_factor),
        virtual_start_(static_cast<std::uint32_t>(g.nodes.size())) {}

  std::size_t key_count() const { return g_.nodes.size() + 1; }
  std::uint64_t key(State s) const { return s; }
  State virtual_start() const { return virtual_start_; }

  template <class Emit>
  void expand(State s, Emit&& emit) const {
    if (s == virtual_start_) {
      const FootEdge& e = g_.edges[start_.edge];
      emit(e.a, start_.t * cost_[start_.edge]);
      emit(e.b, (1.0 - start_.t) * cost_[start_.edge]);
      return;
    }
    for (std::uint32_t i = g_.offsets[s]; i < g_.offsets[s + 1]; ++i) {
      const std::uint32_t e = g_.adjacency[i];
      emit(g_.other(e, s), cost_[e]);
    }
  }

  double heuristic(State s) const {
    if (s == virtual_start_) return 0.0;
    const FootNode& n = g_.nodes[s];
    // The sphere differs from the ellipsoid's edge lengths by < 0.7 %: 0.99 keeps it a lower bound.
    return 0.99 * min_factor_ * haversine_m(n.lat_deg, n.lon_deg, goal_.point.lat_deg, goal_.point.lon_deg);
  }

  std::optional<double> goal_cost(State s) const {
    const FootEdge& e = g_.edges[goal_.edge];
    const double c = cost_[goal_.edge];
    if (s == virtual_start_) {
      if (start_.edge == goal_.edge) return std::abs(start_.t - goal_.t) * c;
      return std::nullopt;
    }
    if (s == e.a) return goal_.t * c;
    if (s == e.b) return (1.0 - goal_.t) * c;
    return std::nullopt;
  }

 private:
  const FootGraph& g_;
  const std::vector<double>& cost_;
  EdgeSnap start_, goal_;
  double min_factor_;
  std::uint32_t virtual_start_;
};

std::string named_road_at(const FootGraph& g, std::uint32_t node) {
  for (std::uint32_t i = g.offsets[node]; i < g.offsets[node + 1]; ++i) {
    const FootWay& w = g.ways[g.edges[g.adjacency[i]].way];
    if (w.is_road() && !w.name.empty()) return w.name;
  }
  return {};
}

}  // namespace

const char* to_string(RouteStatus status) {
  switch (status) {
    case RouteStatus::kFound: return "found";
    case RouteStatus::kOffGraph: return "off_graph";
    case RouteStatus::kUnreachable: return "unreachable";
    case RouteStatus::kSearchLimit: return "search_limit";
    case RouteStatus::kEmptyGraph: return "empty_graph";
    case RouteStatus::kInvalidInput: return "invalid_input";
  }
  return "?";
}

bool valid_lat_lon(const GeoPoint& p) {
  return std::isfinite(p.lat_deg) && std::isfinite(p.lon_deg) && std::abs(p.lat_deg) <= 90.0 &&
         std::abs(p.lon_deg) <= 180.0;
}

namespace {
const FootRouteConfig kFootRouterDefaults;
const ConfigKey<double> kSidewalkFactor{"planning.route.sidewalk_factor", kFootRouterDefaults.sidewalk_factor, {1.0, 100.0},
    "cost factor of a sidewalk"};
const ConfigKey<double> kFootwayFactor{"planning.route.footway_factor", kFootRouterDefaults.footway_factor, {1.0, 100.0},
    "cost factor of a footway, path or pedestrian way"};
const ConfigKey<double> kCrossingWayFactor{"planning.route.crossing_way_factor", kFootRouterDefaults.crossing_way_factor, {1.0, 100.0},
    "cost factor of the length of a footway=crossing"};
const ConfigKey<double> kRoadSidewalkFactor{"planning.route.road_sidewalk_factor", kFootRouterDefaults.road_sidewalk_factor, {1.0, 100.0},
    "cost factor of a road with a sidewalk=* tag"};
const ConfigKey<double> kRoadFactor{"planning.route.road_factor", kFootRouterDefaults.road_factor, {1.0, 100.0},
    "cost factor of a road without a sidewalk"};
const ConfigKey<double> kStepsFactor{"planning.route.steps_factor", kFootRouterDefaults.steps_factor, {1.0, 100.0},
    "cost factor of steps"};
const ConfigKey<double> kAvoidStepsFactor{"planning.route.avoid_steps_factor", kFootRouterDefaults.avoid_steps_factor, {1.0, 1e4},
    "avoid_steps: steps cost this factor more"};
const ConfigKey<double> kCrossingSignalsM{"planning.route.crossing_signals_m", kFootRouterDefaults.crossing_signals_m, {0.0, 1e4},
    "penalty of a signalled crossing [m]"};
const ConfigKey<double> kCrossingMarkedM{"planning.route.crossing_marked_m", kFootRouterDefaults.crossing_marked_m, {0.0, 1e4},
    "penalty of a marked (zebra) crossing [m]"};
const ConfigKey<double> kCrossingUncontrolledM{"planning.route.crossing_uncontrolled_m", kFootRouterDefaults.crossing_uncontrolled_m, {0.0, 1e4},
    "penalty of an uncontrolled crossing [m]"};
const ConfigKey<double> kCrossingUnmarkedM{"planning.route.crossing_unmarked_m", kFootRouterDefaults.crossing_unmarked_m, {0.0, 1e4},
    "penalty of an unmarked crossing [m]"};
const ConfigKey<double> kCrossingUnknownM{"planning.route.crossing_unknown_m", kFootRouterDefaults.crossing_unknown_m, {0.0, 1e4},
    "penalty of a crossing of unknown control [m]"};
const ConfigKey<double> kTactileFactor{"planning.route.tactile_factor", kFootRouterDefaults.tactile_factor, {0.0, 1.0},
    "tactile paving multiplies a crossing's penalty by this"};
const ConfigKey<double> kMaxSnapM{"planning.route.max_snap_m", kFootRouterDefaults.max_snap_m, {0.1, 1e4},
    "a point farther than this from every edge is off the graph [m]"};
const ConfigKey<double> kMaxTimeS{"planning.route.max_time_s", kFootRouterDefaults.max_time_s, {0.0, 3600.0},
    "wall-clock limit of a route search [s]; 0 = none"};
const ConfigKey<bool> kAvoidSteps{"planning.route.avoid_steps", kFootRouterDefaults.avoid_steps,
    "steps cost avoid_steps_factor times more"};
const ConfigKey<long long> kFootRouterMaxExpansions{"planning.route.max_expansions",
                                          static_cast<long long>(kFootRouterDefaults.max_expansions), 1, 1'000'000'000,
                                          "a route search stops after this many expansions"};
}  // namespace

ConfigSchema foot_route_config_schema() {
  ConfigSchema s;
  s.add(kSidewalkFactor);
  s.add(kFootwayFactor);
  s.add(kCrossingWayFactor);
  s.add(kRoadSidewalkFactor);
  s.add(kRoadFactor);
  s.add(kStepsFactor);
  s.add(kAvoidSteps);
  s.add(kAvoidStepsFactor);
  s.add(kCrossingSignalsM);
  s.add(kCrossingMarkedM);
  s.add(kCrossingUncontrolledM);
  s.add(kCrossingUnmarkedM);
  s.add(kCrossingUnknownM);
  s.add(kTactileFactor);
  s.add(kMaxSnapM);
  s.add(kFootRouterMaxExpansions);
  s.add(kMaxTimeS);
  return s;
}

FootRouteConfig foot_route_config(const Config& config) {
  FootRouteConfig c;
  c.sidewalk_factor = get(config, kSidewalkFactor);
  c.footway_factor = get(config, kFootwayFactor);
  c.crossing_way_factor = get(config, kCrossingWayFactor);
  c.road_sidewalk_factor = get(config, kRoadSidewalkFactor);
  c.road_factor = get(config, kRoadFactor);
  c.steps_factor = get(config, kStepsFactor);
  c.avoid_steps = get(config, kAvoidSteps);
  c.avoid_steps_factor = get(config, kAvoidStepsFactor);
  c.crossing_signals_m = get(config, kCrossingSignalsM);
  c.crossing_marked_m = get(config, kCrossingMarkedM);
  c.crossing_uncontrolled_m = get(config, kCrossingUncontrolledM);
  c.crossing_unmarked_m = get(config, kCrossingUnmarkedM);
  c.crossing_unknown_m = get(config, kCrossingUnknownM);
  c.tactile_factor = get(config, kTactileFactor);
  c.max_snap_m = get(config, kMaxSnapM);
  c.max_expansions = static_cast<std::size_t>(get(config, kFootRouterMaxExpansions));
  c.max_time_s = get(config, kMaxTimeS);
  return c;
}

FootRouter::FootRouter(const FootGraph& graph, FootRouteConfig config) : graph_(graph), config_(config) {
  std::vector<double> way_length(graph.ways.size(), 0.0);
  for (const FootEdge& e : graph.edges) way_length[e.way] += e.length_m;
  edge_cost_.resize(graph.edges.size());
  for (std::size_t i = 0; i < graph.edges.size(); ++i) {
    const FootEdge& e = graph.edges[i];
    const FootWay& w = graph.ways[e.way];
    double c = e.length_m * way_factor(config_, w.kind);
    if (w.kind == FootWayKind::kCrossing) {
      // The crossing's penalty once over the whole crossing way, shared by its edges by length.
      const double share = way_length[e.way] > 0 ? e.length_m / way_length[e.way] : 1.0;
      c += share * crossing_penalty(config_, w.crossing);
    } else if (!w.is_road()) {
      // A footway through a crossing node on a road: half the penalty on each side of the node.
      for (const std::uint32_t n : {e.a, e.b}) c += 0.5 * crossing_penalty(config_, graph.nodes[n].crossing);
    }
    edge_cost_[i] = c;
  }
  constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();
  component_.assign(graph.nodes.size(), kUnset);
  std::uint32_t label = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < graph.nodes.size(); ++seed) {
    if (component_[seed] != kUnset) continue;
    component_[seed] = label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      for (std::uint32_t k = graph.offsets[n]; k < graph.offsets[n + 1]; ++k) {
        const std::uint32_t m = graph.other(graph.adjacency[k], n);
        if (component_[m] == kUnset) {
          component_[m] = label;
          stack.push_back(m);
        }
      }
    }
    ++label;
  }
}

std::optional<EdgeSnap> FootRouter::snap(const GeoPoint& p, std::optional<std::uint32_t> component) const {
  if (graph_.edges.empty()) return std::nullopt;
  bool any = false;
  const double mx = std::cos(p.lat_deg * kFootRouterDeg) * kRadius * kFootRouterDeg;  // metres per degree of longitude
  const double my = kRadius * kFootRouterDeg;
  EdgeSnap best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = 0; i < graph_.edges.size(); ++i) {
    if (component && component_[graph_.edges[i].a] != *component) continue;
    any = true;
    const FootNode& a = graph_.nodes[graph_.edges[i].a];
    const FootNode& b = graph_.nodes[graph_.edges[i].b];
    const double ax = (a.lon_deg - p.lon_deg) * mx, ay = (a.lat_deg - p.lat_deg) * my;
    const double bx = (b.lon_deg - p.lon_deg) * mx, by = (b.lat_deg - p.lat_deg) * my;
    const double dx = bx - ax, dy = by - ay;
    const double len2 = dx * dx + dy * dy;
    const double t = len2 > 0 ? std::clamp(-(ax * dx + ay * dy) / len2, 0.0, 1.0) : 0.0;
    const double qx = ax + t * dx, qy = ay + t * dy;
    const double d2 = qx * qx + qy * qy;
    if (d2 < best_d2) {
      best_d2 = d2;
      best.edge = i;
      best.t = t;
      best.point = GeoPoint{a.lat_deg + t * (b.lat_deg - a.lat_deg), a.lon_deg + t * (b.lon_deg - a.lon_deg)};
    }
  }
  if (!any) return std::nullopt;
  best.distance_m = std::sqrt(best_d2);
  return best;
}

Route FootRouter::route(const GeoPoint& from, const GeoPoint& to) const {
  Route r;
  if (!valid_lat_lon(from) || !valid_lat_lon(to)) {
    r.status = RouteStatus::kInvalidInput;
    r.reason = fmt::format("latitude must be in [-90, 90] and longitude in [-180, 180] (from {},{} to {},{})",
                           from.lat_deg, from.lon_deg, to.lat_deg, to.lon_deg);
    return r;
  }
  if (graph_.empty()) {
    r.status = RouteStatus::kEmptyGraph;
    r.reason = "the map has no walkable ways";
    return r;
  }
  EdgeSnap start = *snap(from);
  EdgeSnap goal = *snap(to);
  const std::uint32_t start_component = component_[graph_.edges[start.edge].a];
  const std::uint32_t goal_component = component_[graph_.edges[goal.edge].a];
  if (start_component != goal_component && start.distance_m <= config_.max_snap_m &&
      goal.distance_m <= config_.max_snap_m) {
    // Different pieces of the graph: move one end into the other's piece, the cheaper move first.
    const std::optional<EdgeSnap> goal_moved = snap(to, start_component);
    const std::optional<EdgeSnap> start_moved = snap(from, goal_component);
    const double goal_extra = goal_moved ? goal_moved->distance_m - goal.distance_m : kInf;
    const double start_extra = start_moved ? start_moved->distance_m - start.distance_m : kInf;
    if (goal_extra <= start_extra && goal_moved && goal_moved->distance_m <= config_.max_snap_m) {
      goal = *goal_moved;
    } else if (start_moved && start_moved->distance_m <= config_.max_snap_m) {
      start = *start_moved;
    } else if (goal_moved && goal_moved->distance_m <= config_.max_snap_m) {
      goal = *goal_moved;
    }
  }
  r.start_snap_m = start.distance_m;
  r.goal_snap_m = goal.distance_m;
  for (const auto& [name, s] : {std::pair<const char*, const EdgeSnap&>{"start", start}, {"destination", goal}}) {
    if (s.distance_m > config_.max_snap_m) {
      r.status = RouteStatus::kOffGraph;
      r.reason = fmt::format("the {} is {:.0f} m from the nearest walkable way (planning.route.max_snap_m = {:.0f} m)",
                             name, s.distance_m, config_.max_snap_m);
      return r;
    }
  }
  const double min_factor = std::min({config_.sidewalk_factor, config_.footway_factor, config_.crossing_way_factor,
                                      config_.road_sidewalk_factor, config_.road_factor, config_.steps_factor});
  const FootSpace space(graph_, edge_cost_, start, goal, min_factor);
  SearchLimits limits;
  limits.max_expansions = config_.max_expansions;
  limits.max_time_s = config_.max_time_s;
  const SearchResult<std::uint32_t> result = best_first_search(space, space.virtual_start(), limits);
  r.expanded = result.expanded;
  r.time_s = result.time_s;
  if (!result.found()) {
    if (result.status == SearchStatus::kNoPath) {
      r.status = RouteStatus::kUnreachable;
      r.reason = fmt::format("the destination is not connected to the start by walkable ways ({} nodes searched)",
                             result.expanded);
    } else {
      r.status = RouteStatus::kSearchLimit;
      r.reason = fmt::format("search stopped at its {} limit after {} nodes",
                             result.status == SearchStatus::kTimeLimit ? "time" : "expansion", result.expanded);
    }
    return r;
  }
  r.status = RouteStatus::kFound;
  r.cost = result.cost;

  // Points and the way of each segment.
  std::vector<std::int64_t> node_index;  // graph node per point, -1 for the snapped ends
  r.points.push_back(start.point);
  node_index.push_back(-1);
  for (std::size_t i = 1; i < result.path.size(); ++i) {
    const FootNode& n = graph_.nodes[result.path[i]];
    r.points.push_back(GeoPoint{n.lat_deg, n.lon_deg});
    node_index.push_back(result.path[i]);
  }
  r.points.push_back(goal.point);
  node_index.push_back(-1);
  for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
    std::uint32_t way = graph_.edges[start.edge].way;
    if (i + 2 == r.points.size()) {
      way = graph_.edges[goal.edge].way;
    } else if (i > 0) {
      const auto a = static_cast<std::uint32_t>(node_index[i]);
      const auto b = static_cast<std::uint32_t>(node_index[i + 1]);
      double best = std::numeric_limits<double>::infinity();
      for (std::uint32_t k = graph_.offsets[a]; k < graph_.offsets[a + 1]; ++k) {
        const std::uint32_t e = graph_.adjacency[k];
        if (graph_.other(e, a) == b && edge_cost_[e] < best) {
          best = edge_cost_[e];
          way = graph_.edges[e].way;
        }
      }
    }
    r.segment_way.push_back(way);
  }
  // A snapped end on a graph node adds a zero-length segment (labelled with whichever edge the
  // snap picked): drop it.
  const auto same = [](const GeoPoint& a, const GeoPoint& b) {
    return haversine_m(a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg) < 1e-3;
  };
  if (r.points.size() > 2 && same(r.points[0], r.points[1])) {
    r.points.erase(r.points.begin());
    node_index.erase(node_index.begin());
    r.segment_way.erase(r.segment_way.begin());
  }
  if (r.points.size() > 2 && same(r.points[r.points.size() - 1], r.points[r.points.size() - 2])) {
    r.points.pop_back();
    node_index.pop_back();
    r.segment_way.pop_back();
  }
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    r.node_ids.push_back(node_index[i] >= 0 ? graph_.nodes[static_cast<std::size_t>(node_index[i])].osm_id : 0);
  }

  // Lengths per kind, crossings and steps along the route.
  std::vector<double> at(r.points.size(), 0.0);
  for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
    const double d = ellipsoidal_length_m(r.points[i].lat_deg, r.points[i].lon_deg, r.points[i + 1].lat_deg, r.points[i + 1].lon_deg);
    at[i + 1] = at[i] + d;
    const FootWay& w = graph_.ways[r.segment_way[i]];
    if (w.kind == FootWayKind::kSteps) {
      ++r.steps_segments;
      r.steps_m += d;
    }
    if (w.kind == FootWayKind::kSidewalk) r.sidewalk_m += d;
    if (w.kind == FootWayKind::kRoad) r.road_m += d;
  }
  r.length_m = at.back();
  for (std::size_t i = 0; i < r.segment_way.size();) {
    const FootWay& w = graph_.ways[r.segment_way[i]];
    if (w.kind == FootWayKind::kCrossing) {  // a run of crossing-way segments is one crossing
      RouteCrossing c{i, w.crossing, w.name, at[i]};
      std::size_t j = i;
      for (; j < r.segment_way.size() && graph_.ways[r.segment_way[j]].kind == FootWayKind::kCrossing; ++j) {
        c.info = merge_crossings(c.info, graph_.ways[r.segment_way[j]].crossing);
        for (const std::size_t p : {j, j + 1}) {
          if (node_index[p] >= 0 && c.street.empty()) c.street = named_road_at(graph_, static_cast<std::uint32_t>(node_index[p]));
        }
      }
      r.crossings.push_back(c);
      i = j;
      continue;
    }
    // A crossing node passed on a footway (not while walking along the road it lies on).
    const std::size_t p = i + 1;
    if (p + 1 < r.points.size() && node_index[p] >= 0) {
      const FootNode& n = graph_.nodes[static_cast<std::size_t>(node_index[p])];
      const FootWay& next = graph_.ways[r.segment_way[p]];
      if (n.crossing.is_crossing() && next.kind != FootWayKind::kCrossing && !(w.is_road() && next.is_road())) {
        r.crossings.push_back(RouteCrossing{p, n.crossing, named_road_at(graph_, static_cast<std::uint32_t>(node_index[p])), at[p]});
      }
    }
    ++i;
  }
  return r;
}

}  // namespace navaid::planning
