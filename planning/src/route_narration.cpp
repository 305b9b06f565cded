#include "navaid/planning/route_narration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/route_subgoals.hpp"

namespace navaid::planning {

namespace {


struct Polyline {
  std::vector<Vec2> p;
  std::vector<double> at;
  Vec2 point_at(double s) const {
    s = std::clamp(s, 0.0, at.back());
    const auto it = std::upper_bound(at.begin(), at.end(), s);
    const std::size_t i = it == at.end() ? at.size() - 1 : static_cast<std::size_t>(it - at.begin());
    if (i == 0) return p.front();
    const double len = at[i] - at[i - 1];
    return len > 0 ? p[i - 1] + (s - at[i - 1]) / len * (p[i] - p[i - 1]) : p[i];
  }
};

std::string compass(double heading_rad) {
  static const char* names[] = {"east", "north-east", "north", "north-west", "west", "south-west", "south", "south-east"};
  const double octant = std::round(heading_rad / (M_PI / 4));
  const int k = ((static_cast<int>(octant) % 8) + 8) % 8;
  return names[k];
}

std::string crossing_phrase(const RouteCrossing& c) {
  std::string s = "cross " + (c.street.empty() ? std::string("the road") : c.street);
  switch (c.info.control) {
    case CrossingControl::kTrafficSignals: s += " at traffic signals"; break;
    case CrossingControl::kMarked: s += " at a zebra crossing"; break;
    case CrossingControl::kUncontrolled: s += " at an uncontrolled crossing (no signals)"; break;
    case CrossingControl::kUnmarked: s += " at an unmarked crossing"; break;
    default: s += " at a crossing"; break;
  }
  if (c.info.tactile_paving) s += *c.info.tactile_paving ? ", tactile paving" : ", no tactile paving";
  if (!c.info.kerb.empty()) s += ", kerb " + c.info.kerb;
  if (c.info.island) s += ", traffic island in the middle";
  return s;
}

}  // namespace

namespace {
const NarrationConfig kRouteNarrationDefaults;
const ConfigKey<double> kStraight{"planning.route.narration.straight_deg", kRouteNarrationDefaults.straight_deg, {0.0, 90.0},
                                  "smaller heading changes are not turns [deg]"};
const ConfigKey<double> kSlight{"planning.route.narration.slight_deg", kRouteNarrationDefaults.slight_deg, {0.0, 180.0},
                                "up to this a turn is slight [deg] (>= straight_deg)"};
const ConfigKey<double> kSharp{"planning.route.narration.sharp_deg", kRouteNarrationDefaults.sharp_deg, {0.0, 180.0},
                               "beyond this a turn is sharp [deg] (>= slight_deg)"};
const ConfigKey<double> kTurnWindow{"planning.route.narration.turn_window_m", kRouteNarrationDefaults.turn_window_m, {0.5, 100.0},
                                    "headings are taken over this arc before and after a vertex [m]"};
const ConfigKey<double> kLandmarkRadius{"planning.route.narration.landmark_radius_m", kRouteNarrationDefaults.landmark_radius_m,
                                        {0.0, 1000.0}, "landmarks this close to the destination are named [m]"};
}  // namespace

ConfigSchema narration_config_schema() {
  return ConfigSchema().add(kStraight).add(kSlight).add(kSharp).add(kTurnWindow).add(kLandmarkRadius);
}

NarrationConfig narration_config(const Config& config) {
  NarrationConfig c;
  c.straight_deg = get(config, kStraight);
  c.slight_deg = get(config, within(kSlight, {c.straight_deg, 180.0}));
  c.sharp_deg = get(config, within(kSharp, {c.slight_deg, 180.0}));
  c.turn_window_m = get(config, kTurnWindow);
  c.landmark_radius_m = get(config, kLandmarkRadius);
  return c;
}

std::vector<Instruction> narrate_route(const Route& route, const FootGraph& graph, const NarrationConfig& config) {
  std::vector<Instruction> events;
  if (!route.found() || route.points.size() < 2) return events;
  const LocalEnu enu(GeodeticOrigin{route.points.front().lat_deg, route.points.front().lon_deg, 0.0});
  Polyline line;
  for (const GeoPoint& g : route.points) {
    line.p.push_back(enu.to_enu(g));
    line.at.push_back(line.at.empty() ? 0.0 : line.at.back() + (line.p.back() - line.p[line.p.size() - 2]).norm());
  }
  const double total = line.at.back();
  const double w = config.turn_window_m;
  const auto heading = [](const Vec2& a, const Vec2& b) { return std::atan2(b.y() - a.y(), b.x() - a.x()); };
  const auto way_name = [&](std::size_t segment) -> const std::string& { return graph.ways[route.segment_way[segment]].name; };

  {
    Instruction start;
    start.kind = InstructionKind::kStart;
    const Vec2 ahead = line.point_at(std::min(w, total));
    const std::string& name = way_name(0);
    start.text = fmt::format("Head {} {}.", compass(heading(line.p.front(), ahead)),
                             name.empty() ? std::string("along the ") + to_string(graph.ways[route.segment_way[0]].kind)
                                          : "along " + name);
    std::replace(start.text.begin(), start.text.end(), '_', ' ');
    events.push_back(start);
  }

  // Turns: heading change over the window before and after each vertex; of a cluster of candidate
  // vertices closer than the window, the largest change is kept.
  struct Candidate {
    std::size_t i;
    double delta;
  };
  std::vector<Candidate> candidates;
  const double straight = config.straight_deg * M_PI / 180.0;
  for (std::size_t i = 1; i + 1 < line.p.size(); ++i) {
    const Vec2 before = line.point_at(line.at[i] - w);
    const Vec2 after = line.point_at(line.at[i] + w);
    if ((line.p[i] - before).norm() < 0.25 * w || (after - line.p[i]).norm() < 0.25 * w) continue;
    const double delta = std::remainder(heading(line.p[i], after) - heading(before, line.p[i]), 2 * M_PI);
    if (std::abs(delta) >= straight) candidates.push_back({i, delta});
  }
  for (std::size_t k = 0; k < candidates.size();) {
    std::size_t best = k, j = k + 1;
    for (; j < candidates.size() && line.at[candidates[j].i] - line.at[candidates[j - 1].i] <= w; ++j) {
      if (std::abs(candidates[j].delta) > std::abs(candidates[best].delta)) best = j;
    }
    const Candidate& c = candidates[best];
    const double deg = c.delta * 180.0 / M_PI;
    const double mag = std::abs(deg);
    Instruction t;
    t.kind = InstructionKind::kTurn;
    t.at_m = line.at[c.i];
    t.turn_deg = deg;
    const std::string side = deg > 0 ? "left" : "right";
    const std::string how = mag <= config.slight_deg ? "slight " : mag >= config.sharp_deg ? "sharp " : "";
    const std::string& next = way_name(c.i);
    const std::string onto = !next.empty() && (c.i == 0 || next != way_name(c.i - 1)) ? " onto " + next : "";
    t.text = "turn " + how + side + onto;
    if (!onto.empty()) t.road = next;
    events.push_back(t);
    k = j;
  }

  for (const RouteCrossing& c : route.crossings) {
    Instruction x;
    x.kind = InstructionKind::kCrossing;
    x.at_m = line.at[std::min(c.point, line.at.size() - 1)];
    x.text = crossing_phrase(c);
    x.road = c.street;
    events.push_back(x);
  }

  for (std::size_t i = 0; i < route.segment_way.size();) {
    if (graph.ways[route.segment_way[i]].kind != FootWayKind::kSteps) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < route.segment_way.size() && graph.ways[route.segment_way[j]].kind == FootWayKind::kSteps) ++j;
    Instruction s;
    s.kind = InstructionKind::kSteps;
    s.at_m = line.at[i];
    s.text = fmt::format("steps for {:.0f} m", line.at[j] - line.at[i]);
    events.push_back(s);
    i = j;
  }

  {
    Instruction a;
    a.kind = InstructionKind::kArrive;
    a.at_m = total;
    const Landmark* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    const GeoPoint& goal = route.points.back();
    for (const Landmark& l : graph.landmarks) {
      const double d = haversine_m(goal.lat_deg, goal.lon_deg, l.lat_deg, l.lon_deg);
      if (d <= config.landmark_radius_m && d < best_d) {
        best_d = d;
        best = &l;
      }
    }
    if (best != nullptr) {
      const Vec2 d = line.p.back() - line.point_at(total - w);
      const Vec2 v = enu.to_enu(GeoPoint{best->lat_deg, best->lon_deg}) - line.p.back();
      const double cross = d.x() * v.y() - d.y() * v.x();
      const std::string side = std::abs(cross) < 1e-9 ? "ahead" : cross > 0 ? "on your left" : "on your right";
      a.text = fmt::format("the destination is {} ({}), {}", best->name, best->kind, side);
    } else {
      a.text = "you have arrived at the destination";
    }
    events.push_back(a);
  }

  std::stable_sort(events.begin() + 1, events.end(),
                   [](const Instruction& x, const Instruction& y) { return x.at_m < y.at_m; });
  double previous = 0;
  for (std::size_t k = 1; k < events.size(); ++k) {
    const double d = events[k].at_m - previous;
    std::string& t = events[k].text;
    t[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
    t = (d < 2.0 ? std::string("Then ") + static_cast<char>(std::tolower(static_cast<unsigned char>(t[0]))) + t.substr(1)
                 : fmt::format("After {:.0f} m, {}{}", d, static_cast<char>(std::tolower(static_cast<unsigned char>(t[0]))), t.substr(1))) +
        ".";
    previous = events[k].at_m;
  }
  return events;
}

}  // namespace navaid::planning
