// The street scenarios as OpenStreetMap XML: a strict reader of the published OSM XML 0.6 subset
// checks the export (ids, references, coordinates, the tag contract, shared nodes), the route
// truth is checked against an independent shortest walk over the parsed file and against the
// scenario's path, and the street layouts against the worlds' surfaces.
#include "navaid/simulation/osm_export.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <queue>
#include <regex>
#include <set>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/scenario.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

// ---- a strict reader of the OSM XML 0.6 subset navaid writes ----------------------------------

struct XNode {
  std::int64_t id = 0;
  double lat = 0, lon = 0;
  std::string lat_text, lon_text;
  std::map<std::string, std::string> tags;
};
struct XWay {
  std::int64_t id = 0;
  std::vector<std::int64_t> refs;
  std::map<std::string, std::string> tags;
};
struct XOsm {
  std::map<std::string, std::string> root, bounds;
  std::vector<XNode> nodes;
  std::vector<XWay> ways;
};

std::string decode(const std::string& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] == '<' || v[i] == '>' || v[i] == '"') throw std::runtime_error("raw markup character in a value: " + v);
    if (v[i] != '&') {
      out += v[i];
      continue;
    }
    const std::size_t semi = v.find(';', i);
    if (semi == std::string::npos) throw std::runtime_error("unterminated entity in " + v);
    const std::string ent = v.substr(i, semi - i + 1);
    static const std::map<std::string, char> known = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    const auto it = known.find(ent);
    if (it == known.end()) throw std::runtime_error("unknown entity " + ent);
    out += it->second;
    i = semi;
  }
  return out;
}

struct Tag {
  std::string name;
  std::map<std::string, std::string> attrs;
  bool closing = false, self_closing = false;
};

// Reads the next tag at pos (skipping whitespace between tags; text content is an error).
Tag next_tag(const std::string& x, std::size_t& pos) {
  while (pos < x.size() && std::isspace(static_cast<unsigned char>(x[pos]))) ++pos;
  if (pos >= x.size() || x[pos] != '<') throw std::runtime_error("expected '<' at " + std::to_string(pos));
  const std::size_t end = x.find('>', pos);
  if (end == std::string::npos) throw std::runtime_error("unterminated tag");
  std::string body = x.substr(pos + 1, end - pos - 1);
  pos = end + 1;
  Tag t;
  if (!body.empty() && body[0] == '/') {
    t.closing = true;
    t.name = body.substr(1);
    return t;
  }
  if (!body.empty() && body.back() == '/') {
    t.self_closing = true;
    body.pop_back();
  }
  std::size_t i = 0;
  while (i < body.size() && !std::isspace(static_cast<unsigned char>(body[i]))) ++i;
  t.name = body.substr(0, i);
  while (true) {
    while (i < body.size() && std::isspace(static_cast<unsigned char>(body[i]))) ++i;
    if (i >= body.size()) break;
    const std::size_t eq = body.find('=', i);
    if (eq == std::string::npos || eq + 1 >= body.size() || body[eq + 1] != '"')
      throw std::runtime_error("malformed attribute in <" + t.name + ">");
    const std::string key = body.substr(i, eq - i);
    const std::size_t close = body.find('"', eq + 2);
    if (close == std::string::npos) throw std::runtime_error("unterminated attribute value in <" + t.name + ">");
    if (!t.attrs.emplace(key, decode(body.substr(eq + 2, close - eq - 2))).second)
      throw std::runtime_error("duplicate attribute " + key);
    i = close + 1;
  }
  return t;
}

std::int64_t positive_id(const std::string& s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) throw std::runtime_error("bad id " + s);
  const std::int64_t id = std::stoll(s);
  if (id <= 0) throw std::runtime_error("non-positive id " + s);
  return id;
}

void expect_only(const Tag& t, const std::set<std::string>& allowed) {
  for (const auto& [k, v] : t.attrs)
    if (!allowed.count(k)) throw std::runtime_error("unexpected attribute " + k + " on <" + t.name + ">");
  for (const auto& k : allowed)
    if (!t.attrs.count(k)) throw std::runtime_error("missing attribute " + k + " on <" + t.name + ">");
}

std::pair<std::string, std::string> read_kv(const Tag& t) {
  expect_only(t, {"k", "v"});
  if (!t.self_closing) throw std::runtime_error("<tag> must be empty");
  return {t.attrs.at("k"), t.attrs.at("v")};
}

XOsm parse_osm(const std::string& x) {
  const std::string decl = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>";
  if (x.rfind(decl, 0) != 0) throw std::runtime_error("missing XML declaration");
  std::size_t pos = decl.size();
  XOsm o;
  Tag root = next_tag(x, pos);
  if (root.name != "osm" || root.self_closing) throw std::runtime_error("root is not <osm>");
  expect_only(root, {"version", "generator"});
  o.root = root.attrs;
  bool seen_bounds = false, seen_way = false;
  while (true) {
    Tag t = next_tag(x, pos);
    if (t.closing) {
      if (t.name != "osm") throw std::runtime_error("unexpected </" + t.name + ">");
      break;
    }
    if (t.name == "bounds") {
      if (seen_bounds || !o.nodes.empty() || !t.self_closing) throw std::runtime_error("misplaced <bounds>");
      expect_only(t, {"minlat", "minlon", "maxlat", "maxlon"});
      o.bounds = t.attrs;
      seen_bounds = true;
    } else if (t.name == "node") {
      if (seen_way) throw std::runtime_error("node after the ways");
      expect_only(t, {"id", "lat", "lon", "version", "visible"});
      XNode n;
      n.id = positive_id(t.attrs.at("id"));
      n.lat_text = t.attrs.at("lat");
      n.lon_text = t.attrs.at("lon");
      n.lat = std::stod(n.lat_text);
      n.lon = std::stod(n.lon_text);
      if (t.attrs.at("version") != "1" || t.attrs.at("visible") != "true") throw std::runtime_error("bad version/visible");
      if (!t.self_closing) {
        while (true) {
          Tag c = next_tag(x, pos);
          if (c.closing && c.name == "node") break;
          if (c.name != "tag") throw std::runtime_error("unexpected <" + c.name + "> in a node");
          if (!n.tags.insert(read_kv(c)).second) throw std::runtime_error("duplicate key on a node");
        }
      }
      o.nodes.push_back(n);
    } else if (t.name == "way") {
      seen_way = true;
      expect_only(t, {"id", "version", "visible"});
      if (t.self_closing) throw std::runtime_error("empty way");
      XWay w;
      w.id = positive_id(t.attrs.at("id"));
      while (true) {
        Tag c = next_tag(x, pos);
        if (c.closing && c.name == "way") break;
        if (c.name == "nd") {
          expect_only(c, {"ref"});
          if (!c.self_closing || !w.tags.empty()) throw std::runtime_error("misplaced <nd>");
          w.refs.push_back(positive_id(c.attrs.at("ref")));
        } else if (c.name == "tag") {
          if (!w.tags.insert(read_kv(c)).second) throw std::runtime_error("duplicate key on a way");
        } else {
          throw std::runtime_error("unexpected <" + c.name + "> in a way");
        }
      }
      o.ways.push_back(w);
    } else {
      throw std::runtime_error("unexpected <" + t.name + ">");
    }
  }
  while (pos < x.size() && std::isspace(static_cast<unsigned char>(x[pos]))) ++pos;
  if (pos != x.size()) throw std::runtime_error("content after </osm>");
  if (!seen_bounds) throw std::runtime_error("no <bounds>");
  return o;
}

// ---- checks ------------------------------------------------------------------------------------

std::string tag_or(const std::map<std::string, std::string>& tags, const std::string& k) {
  const auto it = tags.find(k);
  return it == tags.end() ? "" : it->second;
}

// The contract every OSM router of navaid reads, checked on the parsed file.
void check_contract(const XOsm& o, const Scenario& s) {
  EXPECT_EQ(o.root.at("version"), "0.6");
  EXPECT_EQ(o.root.at("generator"), "navaid");
  const std::regex seven(R"(-?\d{1,3}\.\d{7})");
  std::map<std::int64_t, const XNode*> nodes;
  const double minlat = std::stod(o.bounds.at("minlat")), maxlat = std::stod(o.bounds.at("maxlat"));
  const double minlon = std::stod(o.bounds.at("minlon")), maxlon = std::stod(o.bounds.at("maxlon"));
  for (const XNode& n : o.nodes) {
    EXPECT_TRUE(nodes.emplace(n.id, &n).second) << "duplicate node id " << n.id;
    EXPECT_TRUE(std::regex_match(n.lat_text, seven)) << n.lat_text;
    EXPECT_TRUE(std::regex_match(n.lon_text, seven)) << n.lon_text;
    EXPECT_GE(n.lat, -90.0);
    EXPECT_LE(n.lat, 90.0);
    EXPECT_GE(n.lon, -180.0);
    EXPECT_LE(n.lon, 180.0);
    EXPECT_TRUE(n.lat >= minlat && n.lat <= maxlat && n.lon >= minlon && n.lon <= maxlon) << "node " << n.id << " outside <bounds>";
    if (n.tags.count("name")) {
      EXPECT_TRUE(n.tags.count("amenity") || n.tags.count("shop")) << "landmark " << n.tags.at("name");
    }
  }
  // Within the scene, and no two nodes at one place (sidewalks and crossings meet at shared nodes).
  const LocalEnuFrame enu(s.origin);
  std::vector<Vec2> xy;
  for (const XNode& n : o.nodes) {
    const Vec3 p = enu.to_enu(n.lat, n.lon, s.origin.height_m);
    EXPECT_TRUE(p.x() >= s.extent.min.x() - 1.0 && p.x() <= s.extent.max.x() + 1.0 && p.y() >= s.extent.min.y() - 1.0 &&
                p.y() <= s.extent.max.y() + 1.0)
        << "node " << n.id << " at " << p.transpose() << " outside the scenario";
    xy.emplace_back(p.x(), p.y());
  }
  for (std::size_t i = 0; i < xy.size(); ++i)
    for (std::size_t j = i + 1; j < xy.size(); ++j) EXPECT_GT((xy[i] - xy[j]).norm(), 0.01) << "nodes " << o.nodes[i].id << ", " << o.nodes[j].id;

  std::set<std::int64_t> way_ids, sidewalk_nodes;
  for (const XWay& w : o.ways)
    if (tag_or(w.tags, "footway") == "sidewalk") {
      sidewalk_nodes.insert(w.refs.begin(), w.refs.end());
    }
  std::size_t crossings = 0;
  for (const XWay& w : o.ways) {
    EXPECT_TRUE(way_ids.insert(w.id).second) << "duplicate way id " << w.id;
    EXPECT_GE(w.refs.size(), 2u);
    for (const std::int64_t r : w.refs) EXPECT_TRUE(nodes.count(r)) << "way " << w.id << " refers to missing node " << r;
    const std::string highway = tag_or(w.tags, "highway");
    if (highway == "footway") {
      const std::string kind = tag_or(w.tags, "footway");
      EXPECT_TRUE(kind == "sidewalk" || kind == "crossing") << "way " << w.id;
      if (kind == "crossing") {
        ++crossings;
        ASSERT_EQ(w.refs.size(), 3u) << "crossing way " << w.id;
        const XNode& mid = *nodes.at(w.refs[1]);
        EXPECT_EQ(tag_or(mid.tags, "highway"), "crossing");
        const std::string c = tag_or(mid.tags, "crossing");
        EXPECT_TRUE(c == "traffic_signals" || c == "uncontrolled") << c;
        const std::string tp = tag_or(mid.tags, "tactile_paving");
        EXPECT_TRUE(tp.empty() || tp == "yes" || tp == "no") << tp;
        EXPECT_TRUE(sidewalk_nodes.count(w.refs.front()) && sidewalk_nodes.count(w.refs.back()))
            << "crossing way " << w.id << " does not end on sidewalks";
      }
    } else {
      EXPECT_EQ(highway, "residential") << "way " << w.id;
      EXPECT_FALSE(tag_or(w.tags, "name").empty()) << "road way " << w.id << " without a name";
    }
  }
  EXPECT_EQ(crossings, scenario_streets(s).crossings.size());
}

// Shortest walk over the parsed footways (geodesic edge lengths) between the nodes nearest two points.
double shortest_footway_walk(const XOsm& o, double lat0, double lon0, double lat1, double lon1,
                             std::vector<std::int64_t>* crossing_nodes) {
  std::map<std::int64_t, const XNode*> nodes;
  for (const XNode& n : o.nodes) nodes[n.id] = &n;
  std::map<std::int64_t, std::vector<std::pair<std::int64_t, double>>> adj;
  for (const XWay& w : o.ways) {
    if (tag_or(w.tags, "highway") != "footway") continue;
    for (std::size_t k = 0; k + 1 < w.refs.size(); ++k) {
      const XNode &a = *nodes.at(w.refs[k]), &b = *nodes.at(w.refs[k + 1]);
      const double d = geodesic_inverse(a.lat, a.lon, b.lat, b.lon).distance_m;
      adj[a.id].emplace_back(b.id, d);
      adj[b.id].emplace_back(a.id, d);
    }
  }
  auto nearest = [&](double lat, double lon) {
    std::int64_t best = 0;
    double best_d = 1e18;
    for (const auto& [id, e] : adj) {
      const double d = geodesic_inverse(lat, lon, nodes.at(id)->lat, nodes.at(id)->lon).distance_m;
      if (d < best_d) best_d = d, best = id;
    }
    EXPECT_LT(best_d, 0.05);
    return best;
  };
  const std::int64_t from = nearest(lat0, lon0), to = nearest(lat1, lon1);
  std::map<std::int64_t, double> dist;
  std::map<std::int64_t, std::int64_t> prev;
  using Item = std::pair<double, std::int64_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  dist[from] = 0.0;
  q.emplace(0.0, from);
  while (!q.empty()) {
    const auto [d, u] = q.top();
    q.pop();
    if (d > dist[u]) continue;
    if (u == to) break;
    for (const auto& [v, w] : adj[u])
      if (!dist.count(v) || d + w < dist[v]) dist[v] = d + w, prev[v] = u, q.emplace(d + w, v);
  }
  if (!dist.count(to)) return -1.0;
  if (crossing_nodes)
    for (std::int64_t v = to;; v = prev.at(v)) {
      if (tag_or(nodes.at(v)->tags, "highway") == "crossing") crossing_nodes->insert(crossing_nodes->begin(), v);
      if (v == from) break;
    }
  return dist.at(to);
}

// ---- tests -------------------------------------------------------------------------------------

TEST(OsmExport, XmlEscapeCoversTheFiveMarkupCharacters) {
  EXPECT_EQ(xml_escape("a&b<c>d\"e'f"), "a&amp;b&lt;c&gt;d&quot;e&apos;f");
  EXPECT_EQ(xml_escape("Kexing Unit"), "Kexing Unit");
  EXPECT_EQ(decode(xml_escape("Tom & Jerry's <\"shop\">")), "Tom & Jerry's <\"shop\">");
}

TEST(OsmExport, StrictReaderRejectsBrokenFiles) {
  const std::string head = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"navaid\">\n"
                           "  <bounds minlat=\"1.0000000\" minlon=\"1.0000000\" maxlat=\"1.0000000\" maxlon=\"1.0000000\"/>\n";
  EXPECT_NO_THROW(parse_osm(head + "</osm>\n"));
  EXPECT_THROW(parse_osm(head), std::runtime_error);                                                     // no </osm>
  EXPECT_THROW(parse_osm(head + "<node id=\"0\" lat=\"1\" lon=\"1\" version=\"1\" visible=\"true\"/></osm>"), std::runtime_error);
  EXPECT_THROW(parse_osm(head + "<node id=\"1\" lat=\"1\" lon=\"1\" version=\"1\" visible=\"true\">"
                                "<tag k=\"name\" v=\"a & b\"/></node></osm>"),
               std::runtime_error);                                                                      // raw &
  EXPECT_THROW(parse_osm(head + "<relation id=\"1\"/></osm>"), std::runtime_error);
}

class StreetScenario : public ::testing::TestWithParam<const char*> {};

TEST_P(StreetScenario, ExportParsesStrictlyAndKeepsTheTagContract) {
  const Scenario s = make_scenario(GetParam());
  const OsmExport e = export_osm(s);
  XOsm o;
  try {
    o = parse_osm(osm_xml(e));
  } catch (const std::exception& ex) {
    FAIL() << GetParam() << ": " << ex.what();
  }
  EXPECT_EQ(o.nodes.size(), e.nodes.size());
  EXPECT_EQ(o.ways.size(), e.ways.size());
  check_contract(o, s);
}

TEST_P(StreetScenario, RouteTruthMatchesTheScenarioPathAndAnIndependentWalk) {
  const Scenario s = make_scenario(GetParam());
  const OsmExport e = export_osm(s);
  const OsmRouteTruth& t = e.truth;
  const double path_m = polyline_length(s.path);
  EXPECT_NEAR(t.length_m, path_m, 1e-6);
  EXPECT_NEAR(t.geodesic_length_m, path_m, 0.05);  // ENU vs ellipsoid over ~300 m
  const LocalEnuFrame enu(s.origin);
  const Vec3 start = enu.to_enu(t.start_lat_deg, t.start_lon_deg, s.origin.height_m);
  const Vec3 goal = enu.to_enu(t.goal_lat_deg, t.goal_lon_deg, s.origin.height_m);
  EXPECT_LT((start.head<2>() - s.path.front()).norm(), 0.02);
  EXPECT_LT((goal.head<2>() - s.path.back()).norm(), 0.02);

  // The shortest walk over the parsed file is the scenario's route (it is straight or L-shaped).
  const XOsm o = parse_osm(osm_xml(e));
  std::vector<std::int64_t> crossing_nodes;
  const double walk = shortest_footway_walk(o, t.start_lat_deg, t.start_lon_deg, t.goal_lat_deg, t.goal_lon_deg, &crossing_nodes);
  EXPECT_NEAR(walk, path_m, 0.05);
  ASSERT_EQ(crossing_nodes.size(), t.crossings.size());
  for (std::size_t i = 0; i < t.crossings.size(); ++i) EXPECT_EQ(crossing_nodes[i], t.crossings[i].node_id);
  const auto landmark = std::find_if(o.nodes.begin(), o.nodes.end(), [&](const XNode& n) { return n.id == t.landmark_node_id; });
  ASSERT_NE(landmark, o.nodes.end());
  EXPECT_EQ(tag_or(landmark->tags, "name"), t.landmark_name);
  // The landmark stands a few metres from the goal, facing the walker.
  const Vec3 lm = enu.to_enu(landmark->lat, landmark->lon, s.origin.height_m);
  EXPECT_LT((lm.head<2>() - s.path.back()).norm(), 5.0);
}

TEST_P(StreetScenario, OutputIsDeterministicForASeed) {
  ScenarioOptions options;
  options.seed = 7;
  const OsmExport a = export_osm(make_scenario(GetParam(), options));
  const OsmExport b = export_osm(make_scenario(GetParam(), options));
  EXPECT_EQ(osm_xml(a), osm_xml(b));
  EXPECT_EQ(osm_truth_json(a), osm_truth_json(b));
  EXPECT_EQ(a.seed, 7u);
  EXPECT_NE(osm_truth_json(a).find("\"seed\": 7"), std::string::npos);
}

// The layouts are the centre lines of what the builders put into the worlds: looking straight down,
// sidewalk lines see sidewalk (or tactile paving) at the walking surface, roads and crossings see
// road or crosswalk a step lower, landmarks see their board, building or shelter.
TEST_P(StreetScenario, LayoutsLieOnTheWorldsSurfaces) {
  const Scenario s = make_scenario(GetParam());
  const StreetMap m = scenario_streets(s);
  const RayCaster caster(s.world);
  const Vec3 down(0.0, 0.0, -1.0);
  auto look = [&](const Vec2& p, double from_z) { return caster.cast(Vec3(p.x(), p.y(), from_z), down); };
  auto along = [](const std::vector<Vec2>& line, const std::function<void(const Vec2&)>& f) {
    for (std::size_t k = 0; k + 1 < line.size(); ++k) {
      const double len = (line[k + 1] - line[k]).norm();
      for (double d = 0.3; d < len - 0.3; d += 0.5) f(line[k] + d / len * (line[k + 1] - line[k]));
    }
  };
  int checked = 0;
  for (const auto& w : m.sidewalks)
    along(w, [&](const Vec2& p) {
      const auto h = look(p, s.ground_z_m + 0.05);
      ASSERT_TRUE(h) << p.transpose();
      EXPECT_TRUE(h->semantic == SemanticClass::kSidewalk || h->semantic == SemanticClass::kTactilePaving)
          << "sidewalk line at " << p.transpose() << " sees class " << static_cast<int>(h->semantic);
      EXPECT_NEAR(h->point.z(), s.ground_z_m, 0.01);
      ++checked;
    });
  auto on_road = [&](const Vec2& p, const char* what) {
    const auto h = look(p, s.ground_z_m - 0.1);
    ASSERT_TRUE(h) << p.transpose();
    EXPECT_TRUE(h->semantic == SemanticClass::kRoad || h->semantic == SemanticClass::kCrosswalk)
        << what << " at " << p.transpose() << " sees class " << static_cast<int>(h->semantic);
    ++checked;
  };
  for (const auto& r : m.roads) along(r.line, [&](const Vec2& p) { on_road(p, "road"); });
  for (const auto& c : m.crossings) {
    along({c.from, c.to}, [&](const Vec2& p) {
      on_road(p, "crossing");
      if (c.kerb_height_m) {  // the road a kerb's height below the walked surface
        const auto h = look(p, s.ground_z_m - 0.1);
        ASSERT_TRUE(h);
        EXPECT_NEAR(h->point.z(), s.ground_z_m - *c.kerb_height_m, 0.01) << p.transpose();
      }
    });
    if (c.markings == "zebra") {  // a stripe beside the centre line
      const auto h = look(0.5 * (c.from + c.to) + Vec2(0.0, 0.5), s.ground_z_m - 0.1);
      ASSERT_TRUE(h);
      EXPECT_EQ(h->semantic, SemanticClass::kCrosswalk);
    }
  }
  for (const auto& lm : m.landmarks) {
    const auto h = look(lm.xy, 40.0);
    ASSERT_TRUE(h) << lm.name;
    std::map<std::string, std::string> tags(lm.tags.begin(), lm.tags.end());
    const SemanticClass expected = tags["information"] == "board"        ? SemanticClass::kTrafficSign
                                   : tags["amenity"] == "community_centre" ? SemanticClass::kBuilding
                                   : tags["amenity"] == "shelter"          ? SemanticClass::kBusStop
                                                                           : SemanticClass::kUnlabeled;
    EXPECT_EQ(h->semantic, expected) << "landmark '" << lm.name << "' at " << lm.xy.transpose();
  }
  EXPECT_GT(checked, 500);
}

INSTANTIATE_TEST_SUITE_P(Routes, StreetScenario, ::testing::Values("route1", "route2"));

TEST(OsmExport, Route2CrossesTwoUncontrolledZebrasWithoutTactilePaving) {
  const OsmExport e = export_osm(make_scenario("route2"));
  ASSERT_EQ(e.truth.crossings.size(), 2u);
  for (const RouteCrossing& c : e.truth.crossings) {
    EXPECT_EQ(c.kind, "uncontrolled");
    EXPECT_EQ(c.tactile_paving, "no");
  }
  EXPECT_NEAR(e.truth.crossings[0].at_m, 92.0, 1e-6);
  EXPECT_NEAR(e.truth.crossings[1].at_m, 192.0, 1e-6);
  EXPECT_EQ(e.truth.landmark_name, "Kexing Unit");
  // The low step at both ends of each crossing, on the nodes the crossing shares with the sidewalks.
  std::size_t kerbs = 0;
  for (const OsmNode& n : e.nodes)
    for (const auto& [k, v] : n.tags)
      if (k == "kerb:height") {
        EXPECT_EQ(v, "0.12");
        EXPECT_NEAR(std::abs(n.xy.y()), 0.0, 1e-9);
        ++kerbs;
      }
  EXPECT_EQ(kerbs, 4u);
  const OsmExport r1 = export_osm(make_scenario("route1"));
  EXPECT_TRUE(r1.truth.crossings.empty());
  EXPECT_EQ(r1.truth.landmark_name, "Honoring the Pioneers of Science");
}

TEST(OsmExport, ScenariosWithoutStreetsAreRefused) {
  EXPECT_FALSE(has_streets("corridor"));
  const auto err = testing::expect_throw<ConfigError>([] { export_osm(make_scenario("corridor")); });
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("scenario corridor has no streets to export"), std::string::npos) << err->what();
}

TEST(OsmExport, APathOffTheWalkwaysIsAnError) {
  Scenario s = make_scenario("route1");
  s.path = {Vec2(0.0, 32.0), Vec2(0.0, 0.0), Vec2(120.0, -12.0)};  // straight across the street
  EXPECT_THROW(export_osm(s), Error);
}

}  // namespace
}  // namespace navaid::simulation
