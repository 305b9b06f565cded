// Offline pedestrian routing (docs/routing.md) on the largest real extract,
// liechtenstein-latest.osm.pbf (143 k nodes, 15 k ways): loading + foot-graph building, then route
// queries of growing straight-line length (250 m .. 12 km) from one start. Counters: nodes
// expanded, route length, graph size. Goal: <= 50 ms per query after loading.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "navaid/planning/foot_router.hpp"

namespace {

using namespace navaid::planning;

const std::string kFile = std::string(NAVAID_SHARED_DATA_DIR) + "/osm/liechtenstein-latest.osm.pbf";

const FootGraph& graph() {
  static const FootGraph g = load_osm_foot_graph(kFile);
  return g;
}

/// A start near Vaduz (47.141 N, 9.521 E) and, per distance, the first graph node at that
/// straight-line distance (within 10 %) that the router reaches.
struct Query {
  GeoPoint from, to;
};
const std::vector<Query>& queries() {
  static const std::vector<Query> q = [] {
    const FootGraph& g = graph();
    const FootRouter router(g);
    const GeoPoint start{47.1410, 9.5210};
    std::vector<Query> out;
    for (const double d : {250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0, 12000.0}) {
      Query found{start, start};
      for (std::size_t i = 0; i < g.nodes.size(); i += 7) {
        const double s = haversine_m(start.lat_deg, start.lon_deg, g.nodes[i].lat_deg, g.nodes[i].lon_deg);
        if (s < d || s > 1.1 * d) continue;
        const GeoPoint to{g.nodes[i].lat_deg, g.nodes[i].lon_deg};
        if (router.route(start, to).found()) {
          found.to = to;
          break;
        }
      }
      out.push_back(found);
    }
    return out;
  }();
  return q;
}

void BM_LoadLiechtenstein(benchmark::State& state) {
  std::size_t edges = 0;
  for (auto _ : state) {
    const FootGraph g = load_osm_foot_graph(kFile);
    edges = g.edges.size();
    benchmark::DoNotOptimize(edges);
  }
  state.counters["edges"] = static_cast<double>(edges);
  state.counters["nodes"] = static_cast<double>(graph().nodes.size());
  state.counters["walkable_ways"] = static_cast<double>(graph().stats.walkable_ways);
}
BENCHMARK(BM_LoadLiechtenstein)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_RouteQuery(benchmark::State& state) {
  const Query& q = queries()[static_cast<std::size_t>(state.range(0))];
  const FootRouter router(graph());
  if (q.to.lat_deg == q.from.lat_deg && q.to.lon_deg == q.from.lon_deg) {
    state.SkipWithError("no reachable node at this distance");
    return;
  }
  double length = 0;
  std::size_t expanded = 0;
  bool found = false;
  for (auto _ : state) {
    const Route r = router.route(q.from, q.to);
    length = r.length_m;
    expanded = r.expanded;
    found = r.found();
    // Not DoNotOptimize(double&): its "+m,r" asm operand corrupts doubles under GCC 12 (the counter
    // read garbage); the route's point buffer is a pointer.
    benchmark::DoNotOptimize(r.points.data());
  }
  state.counters["found"] = found ? 1.0 : 0.0;
  state.counters["nodes_expanded"] = static_cast<double>(expanded);
  state.counters["route_m"] = length;
  const double straight = haversine_m(q.from.lat_deg, q.from.lon_deg, q.to.lat_deg, q.to.lon_deg);
  state.counters["straight_m"] = straight;
}
BENCHMARK(BM_RouteQuery)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);

}  // namespace
