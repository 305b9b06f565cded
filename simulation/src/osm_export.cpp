#include "navaid/simulation/osm_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "scenarios/street_layouts.hpp"

namespace navaid::simulation {

namespace {

constexpr double kSnapM = 1e-3;  // points closer than this share one node

enum class LineKind { kSidewalk, kCrossing, kRoad };

struct Line {
  LineKind kind;
  std::vector<Vec2> points;
  OsmTags tags;
  int crossing = -1;  // index into StreetMap::crossings
};

// Distance of p from segment a-b and its parameter along it.
std::pair<double, double> segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return {(a + t * d - p).norm(), t};
}

std::string crossing_kind(CrossingControl c) {
  return c == CrossingControl::kTrafficSignals ? "traffic_signals" : "uncontrolled";
}

std::string json_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        else
          out += c;
    }
  }
  return out;
}

}  // namespace

bool has_streets(std::string_view name) { return name == "route1" || name == "route2"; }

StreetMap scenario_streets(const Scenario& s) {
  if (s.name == "route1") return scenarios::route1_streets();
  if (s.name == "route2") return scenarios::route2_streets();
  throw ConfigError("", "scenario", "scenario " + s.name + " has no streets to export (street scenarios: route1, route2)");
}

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

OsmExport export_osm(const Scenario& s) {
  const StreetMap m = scenario_streets(s);
  const LocalEnuFrame enu(s.origin);

  std::vector<Line> lines;
  for (const auto& w : m.sidewalks) lines.push_back({LineKind::kSidewalk, w, {{"highway", "footway"}, {"footway", "sidewalk"}}});
  for (std::size_t i = 0; i < m.crossings.size(); ++i) {
    const StreetCrossing& c = m.crossings[i];
    lines.push_back({LineKind::kCrossing, {c.from, 0.5 * (c.from + c.to), c.to},
                     {{"highway", "footway"}, {"footway", "crossing"}}, static_cast<int>(i)});
  }
  for (const auto& r : m.roads) {
    OsmTags tags = {{"highway", r.highway}, {"name", r.name}};
    tags.insert(tags.end(), r.extra.begin(), r.extra.end());
    lines.push_back({LineKind::kRoad, r.line, tags});
  }
  for (const Line& l : lines)
    if (l.points.size() < 2) throw Error("OSM export of " + s.name + ": a street line has fewer than two points");

  // Split every line where a vertex of any line or a waypoint of the path lies on it.
  std::vector<Vec2> split_points(s.path.begin(), s.path.end());
  for (const Line& l : lines) split_points.insert(split_points.end(), l.points.begin(), l.points.end());
  for (Line& l : lines) {
    std::vector<Vec2> out{l.points.front()};
    for (std::size_t k = 0; k + 1 < l.points.size(); ++k) {
      const Vec2 a = l.points[k], b = l.points[k + 1];
      std::vector<std::pair<double, Vec2>> inner;
      for (const Vec2& p : split_points) {
        const auto [dist, t] = segment_distance(p, a, b);
        if (dist < kSnapM && (p - a).norm() >= kSnapM && (p - b).norm() >= kSnapM) inner.emplace_back(t, p);
      }
      std::sort(inner.begin(), inner.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (const auto& [t, p] : inner)
        if ((p - out.back()).norm() >= kSnapM) out.push_back(p);
      if ((b - out.back()).norm() >= kSnapM) out.push_back(b);
    }
    l.points = std::move(out);
  }

  OsmExport e;
  e.scenario = s.name;
  e.seed = s.seed;
  e.origin = s.origin;
  std::map<std::pair<long long, long long>, std::int64_t> by_position;
  auto node_at = [&](const Vec2& p) -> std::int64_t {
    const std::pair<long long, long long> key{std::llround(p.x() / kSnapM), std::llround(p.y() / kSnapM)};
    const auto it = by_position.find(key);
    if (it != by_position.end()) return it->second;
    OsmNode n;
    n.id = static_cast<std::int64_t>(e.nodes.size()) + 1;
    n.xy = p;
    const Vec3 g = enu.to_geodetic(Vec3(p.x(), p.y(), s.ground_z_m));
    n.lat_deg = g.x();
    n.lon_deg = g.y();
    e.nodes.push_back(n);
    by_position.emplace(key, n.id);
    return n.id;
  };
  auto node = [&](std::int64_t id) -> OsmNode& { return e.nodes[static_cast<std::size_t>(id - 1)]; };

  // Walkway edges (undirected) -> way index, for the route truth.
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> walk_edges;
  std::vector<int> way_crossing;  // per way: crossing index or -1
  for (const Line& l : lines) {
    OsmWay w;
    w.id = static_cast<std::int64_t>(e.ways.size()) + 1;
    for (const Vec2& p : l.points) {
      const std::int64_t id = node_at(p);
      if (w.nodes.empty() || w.nodes.back() != id) w.nodes.push_back(id);
    }
    w.tags = l.tags;
    if (l.kind == LineKind::kCrossing) {
      const StreetCrossing& c = m.crossings[static_cast<std::size_t>(l.crossing)];
      OsmNode& mid = node(node_at(0.5 * (c.from + c.to)));
      mid.tags.emplace_back("highway", "crossing");
      mid.tags.emplace_back("crossing", crossing_kind(c.control));
      if (c.tactile_paving) mid.tags.emplace_back("tactile_paving", *c.tactile_paving ? "yes" : "no");
      if (!c.markings.empty()) mid.tags.emplace_back("crossing:markings", c.markings);
      if (c.kerb_height_m)
        for (const Vec2& end : {c.from, c.to}) {
          OsmNode& n = node(node_at(end));
          n.tags.emplace_back("kerb", "raised");
          n.tags.emplace_back("kerb:height", fmt::format("{:.2f}", *c.kerb_height_m));
        }
    }
    if (l.kind != LineKind::kRoad)
      for (std::size_t k = 0; k + 1 < w.nodes.size(); ++k)
        walk_edges[std::minmax(w.nodes[k], w.nodes[k + 1])] = e.ways.size();
    way_crossing.push_back(l.crossing);
    e.ways.push_back(std::move(w));
  }
  std::vector<std::int64_t> landmark_ids;
  for (const StreetLandmark& lm : m.landmarks) {
    OsmNode n;
    n.id = static_cast<std::int64_t>(e.nodes.size()) + 1;
    n.xy = lm.xy;
    const Vec3 g = enu.to_geodetic(Vec3(lm.xy.x(), lm.xy.y(), s.ground_z_m));
    n.lat_deg = g.x();
    n.lon_deg = g.y();
    if (!lm.name.empty()) n.tags.emplace_back("name", lm.name);
    n.tags.insert(n.tags.end(), lm.tags.begin(), lm.tags.end());
    landmark_ids.push_back(n.id);
    e.nodes.push_back(std::move(n));
  }
  e.min_lat = e.max_lat = e.nodes.front().lat_deg;
  e.min_lon = e.max_lon = e.nodes.front().lon_deg;
  for (const OsmNode& n : e.nodes) {
    e.min_lat = std::min(e.min_lat, n.lat_deg);
    e.max_lat = std::max(e.max_lat, n.lat_deg);
    e.min_lon = std::min(e.min_lon, n.lon_deg);
    e.max_lon = std::max(e.max_lon, n.lon_deg);
  }

  // The scenario's walk over the walkway graph: along each path segment, the walkway nodes on it in
  // order; each consecutive pair must be a walkway edge.
  OsmRouteTruth& t = e.truth;
  for (std::size_t k = 0; k + 1 < s.path.size(); ++k) {
    const Vec2 a = s.path[k], b = s.path[k + 1];
    std::vector<std::pair<double, std::int64_t>> on;
    for (const auto& [edge, way] : walk_edges)
      for (const std::int64_t id : {edge.first, edge.second}) {
        const auto [dist, par] = segment_distance(node(id).xy, a, b);
        if (dist < kSnapM) on.emplace_back(par, id);
      }
    std::sort(on.begin(), on.end());
    on.erase(std::unique(on.begin(), on.end(), [](const auto& x, const auto& y) { return x.second == y.second; }), on.end());
    if (on.empty() || (node(on.front().second).xy - a).norm() >= kSnapM || (node(on.back().second).xy - b).norm() >= kSnapM)
      throw Error(fmt::format("OSM export of {}: the path segment ({:.2f}, {:.2f}) -> ({:.2f}, {:.2f}) is not on the walkways",
                              s.name, a.x(), a.y(), b.x(), b.y()));
    for (const auto& [par, id] : on) {
      if (!t.node_ids.empty() && t.node_ids.back() == id) continue;
      if (!t.node_ids.empty()) {
        const std::int64_t prev = t.node_ids.back();
        const auto edge = walk_edges.find(std::minmax(prev, id));
        if (edge == walk_edges.end())
          throw Error(fmt::format("OSM export of {}: the path leaves the walkways between ({:.2f}, {:.2f}) and ({:.2f}, {:.2f})",
                                  s.name, node(prev).xy.x(), node(prev).xy.y(), node(id).xy.x(), node(id).xy.y()));
        t.length_m += (node(id).xy - node(prev).xy).norm();
        t.geodesic_length_m +=
            geodesic_inverse(node(prev).lat_deg, node(prev).lon_deg, node(id).lat_deg, node(id).lon_deg).distance_m;
        const int c = way_crossing[edge->second];
        if (c >= 0 && !node(id).tags.empty() && node(id).tags.front() == std::make_pair(std::string("highway"), std::string("crossing"))) {
          const StreetCrossing& sc = m.crossings[static_cast<std::size_t>(c)];
          RouteCrossing rc;
          rc.way_id = e.ways[edge->second].id;
          rc.node_id = id;
          rc.kind = crossing_kind(sc.control);
          rc.tactile_paving = sc.tactile_paving ? (*sc.tactile_paving ? "yes" : "no") : "";
          rc.lat_deg = node(id).lat_deg;
          rc.lon_deg = node(id).lon_deg;
          rc.at_m = t.length_m;
          t.crossings.push_back(rc);
        }
      }
      t.node_ids.push_back(id);
    }
  }
  t.start_W = s.path.front();
  t.goal_W = s.path.back();
  const OsmNode& first = node(t.node_ids.front());
  const OsmNode& last = node(t.node_ids.back());
  t.start_lat_deg = first.lat_deg;
  t.start_lon_deg = first.lon_deg;
  t.goal_lat_deg = last.lat_deg;
  t.goal_lon_deg = last.lon_deg;
  const OsmNode& lm = node(landmark_ids.at(m.goal_landmark));
  t.landmark_name = m.landmarks[m.goal_landmark].name;
  t.landmark_node_id = lm.id;
  t.landmark_lat_deg = lm.lat_deg;
  t.landmark_lon_deg = lm.lon_deg;
  return e;
}

std::string osm_xml(const OsmExport& e) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"navaid\">\n";
  x += fmt::format("  <bounds minlat=\"{:.7f}\" minlon=\"{:.7f}\" maxlat=\"{:.7f}\" maxlon=\"{:.7f}\"/>\n", e.min_lat,
                   e.min_lon, e.max_lat, e.max_lon);
  auto tags = [&x](const OsmTags& t, const char* indent) {
    for (const auto& [k, v] : t) x += fmt::format("{}<tag k=\"{}\" v=\"{}\"/>\n", indent, xml_escape(k), xml_escape(v));
  };
  for (const OsmNode& n : e.nodes) {
    x += fmt::format("  <node id=\"{}\" lat=\"{:.7f}\" lon=\"{:.7f}\" version=\"1\" visible=\"true\"", n.id, n.lat_deg, n.lon_deg);
    if (n.tags.empty()) {
      x += "/>\n";
    } else {
      x += ">\n";
      tags(n.tags, "    ");
      x += "  </node>\n";
    }
  }
  for (const OsmWay& w : e.ways) {
    x += fmt::format("  <way id=\"{}\" version=\"1\" visible=\"true\">\n", w.id);
    for (const std::int64_t id : w.nodes) x += fmt::format("    <nd ref=\"{}\"/>\n", id);
    tags(w.tags, "    ");
    x += "  </way>\n";
  }
  x += "</osm>\n";
  return x;
}

std::string osm_truth_json(const OsmExport& e) {
  const OsmRouteTruth& t = e.truth;
  std::string j = "{\n";
  j += fmt::format("  \"scenario\": \"{}\",\n  \"seed\": {},\n", json_escape(e.scenario), e.seed);
  j += fmt::format("  \"origin\": {{\"lat\": {:.9f}, \"lon\": {:.9f}, \"height_m\": {:.3f}}},\n", e.origin.latitude_deg,
                   e.origin.longitude_deg, e.origin.height_m);
  j += fmt::format("  \"start\": {{\"lat\": {:.7f}, \"lon\": {:.7f}, \"x_m\": {:.3f}, \"y_m\": {:.3f}, \"node_id\": {}}},\n",
                   t.start_lat_deg, t.start_lon_deg, t.start_W.x(), t.start_W.y(), t.node_ids.front());
  j += fmt::format("  \"goal\": {{\"lat\": {:.7f}, \"lon\": {:.7f}, \"x_m\": {:.3f}, \"y_m\": {:.3f}, \"node_id\": {}}},\n",
                   t.goal_lat_deg, t.goal_lon_deg, t.goal_W.x(), t.goal_W.y(), t.node_ids.back());
  j += fmt::format("  \"length_m\": {:.3f},\n  \"geodesic_length_m\": {:.3f},\n", t.length_m, t.geodesic_length_m);
  j += "  \"route_node_ids\": [";
  for (std::size_t i = 0; i < t.node_ids.size(); ++i) j += fmt::format("{}{}", i ? ", " : "", t.node_ids[i]);
  j += "],\n  \"crossings\": [";
  for (std::size_t i = 0; i < t.crossings.size(); ++i) {
    const RouteCrossing& c = t.crossings[i];
    j += fmt::format(
        "{}\n    {{\"way_id\": {}, \"node_id\": {}, \"crossing\": \"{}\", \"tactile_paving\": {}, \"lat\": {:.7f}, "
        "\"lon\": {:.7f}, \"at_m\": {:.3f}}}",
        i ? "," : "", c.way_id, c.node_id, c.kind, c.tactile_paving.empty() ? "null" : "\"" + c.tactile_paving + "\"",
        c.lat_deg, c.lon_deg, c.at_m);
  }
  j += t.crossings.empty() ? "],\n" : "\n  ],\n";
  j += fmt::format("  \"landmark\": {{\"name\": \"{}\", \"node_id\": {}, \"lat\": {:.7f}, \"lon\": {:.7f}}},\n",
                   json_escape(t.landmark_name), t.landmark_node_id, t.landmark_lat_deg, t.landmark_lon_deg);
  j += fmt::format("  \"nodes\": {},\n  \"ways\": {}\n}}\n", e.nodes.size(), e.ways.size());
  return j;
}

void write_osm_export(const OsmExport& e, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir.string(), "cannot create the folder: " + ec.message());
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"map.osm", osm_xml(e)},
                                   std::pair<std::string, std::string>{"osm_truth.json", osm_truth_json(e)}}) {
    const std::filesystem::path p = dir / name;
    std::ofstream f(p, std::ios::binary);
    f << text;
    f.close();
    if (!f) throw IoError(p.string(), "cannot write the file");
  }
}

}  // namespace navaid::simulation
