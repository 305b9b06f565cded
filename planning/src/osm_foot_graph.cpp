#include "navaid/planning/osm_foot_graph.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <unordered_map>

#include <osmium/handler.hpp>
#include <osmium/handler/node_locations_for_ways.hpp>
#include <osmium/index/map/flex_mem.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/osm/node.hpp>
#include <osmium/osm/way.hpp>
#include <osmium/visitor.hpp>

#include "navaid/core/errors.hpp"

namespace navaid::planning {

namespace {

bool one_of(std::string_view v, std::initializer_list<std::string_view> values) {
  return std::find(values.begin(), values.end(), v) != values.end();
}

int rank(CrossingControl c) {
  switch (c) {
    case CrossingControl::kTrafficSignals: return 5;
    case CrossingControl::kMarked: return 4;
    case CrossingControl::kUncontrolled: return 3;
    case CrossingControl::kUnmarked: return 2;
    case CrossingControl::kUnknown: return 1;
    case CrossingControl::kNone: return 0;
  }
  return 0;
}

template <class Object>
OsmTags tags_of(const Object& object) {
  OsmTags tags;
  tags.reserve(object.tags().size());
  for (const osmium::Tag& t : object.tags()) tags.emplace_back(t.key(), t.value());
  return tags;
}

struct WayRecord {
  FootWay way;
  std::vector<std::int64_t> refs;
  std::vector<std::pair<double, double>> lat_lon;  // NaN when the node is missing from the file
};

/// Collects walkable ways (with their node locations, filled by the location handler before this
/// handler sees the way), crossing nodes and landmarks in one pass.
class Collector : public osmium::handler::Handler {
 public:
  void node(const osmium::Node& node) {
    ++stats.osm_nodes;
    if (node.tags().empty() || !node.location().valid()) return;
    const OsmTags tags = tags_of(node);
    const CrossingInfo crossing = crossing_from_tags(tags, false);
    if (crossing.is_crossing()) crossings.emplace(node.id(), crossing);
    const std::string_view name = tag_value(tags, "name");
    if (!name.empty()) {
      for (const char* key : {"amenity", "shop", "tourism"}) {
        const std::string_view v = tag_value(tags, key);
        if (v.empty()) continue;
        landmarks.push_back(Landmark{node.id(), node.location().lat(), node.location().lon(), std::string(name),
                                     std::string(key) + "=" + std::string(v)});
        break;
      }
    }
  }

  void way(const osmium::Way& way) {
    ++stats.osm_ways;
    if (way.tags()["highway"] == nullptr) return;
    const OsmTags tags = tags_of(way);
    const std::optional<FootWayKind> kind = classify_foot_way(tags);
    if (!kind) {
      ++stats.excluded_ways;
      return;
    }
    WayRecord r;
    r.way.osm_id = way.id();
    r.way.kind = *kind;
    r.way.highway = std::string(tag_value(tags, "highway"));
    r.way.name = std::string(tag_value(tags, "name"));
    if (r.way.name.empty()) r.way.name = std::string(tag_value(tags, "ref"));
    if (*kind == FootWayKind::kCrossing) {
      r.way.crossing = crossing_from_tags(tags, true);
      if (!r.way.crossing.is_crossing()) r.way.crossing.control = CrossingControl::kUnknown;
    }
    for (const osmium::NodeRef& n : way.nodes()) {
      r.refs.push_back(n.ref());
      if (n.location().valid()) {
        r.lat_lon.emplace_back(n.location().lat(), n.location().lon());
      } else {
        r.lat_lon.emplace_back(std::nan(""), std::nan(""));
        ++stats.missing_locations;
      }
    }
    ++stats.walkable_ways;
    ways.push_back(std::move(r));
  }

  FootGraphStats stats;
  std::vector<WayRecord> ways;
  std::unordered_map<std::int64_t, CrossingInfo> crossings;
  std::vector<Landmark> landmarks;
};

FootGraph build(Collector& c) {
  FootGraph g;
  g.stats = c.stats;
  g.landmarks = std::move(c.landmarks);
  std::unordered_map<std::int64_t, std::uint32_t> index;
  for (WayRecord& r : c.ways) {
    const auto way_id = static_cast<std::uint32_t>(g.ways.size());
    constexpr std::uint32_t kNoNode = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t previous = kNoNode;
    for (std::size_t i = 0; i < r.refs.size(); ++i) {
      if (std::isnan(r.lat_lon[i].first)) {  // a gap: no edge across a missing node
        previous = kNoNode;
        continue;
      }
      auto [it, inserted] = index.emplace(r.refs[i], static_cast<std::uint32_t>(g.nodes.size()));
      if (inserted) {
        FootNode n;
        n.osm_id = r.refs[i];
        n.lat_deg = r.lat_lon[i].first;
        n.lon_deg = r.lat_lon[i].second;
        if (const auto x = c.crossings.find(r.refs[i]); x != c.crossings.end()) n.crossing = x->second;
        g.nodes.push_back(n);
      }
      const std::uint32_t node = it->second;
      if (r.way.kind == FootWayKind::kCrossing && g.nodes[node].crossing.is_crossing()) {
        r.way.crossing = merge_crossings(r.way.crossing, g.nodes[node].crossing);
      }
      if (previous != kNoNode && previous != node) {
        const FootNode& p = g.nodes[previous];
        const FootNode& q = g.nodes[node];
        g.edges.push_back(FootEdge{previous, node, way_id, ellipsoidal_length_m(p.lat_deg, p.lon_deg, q.lat_deg, q.lon_deg)});
      }
      previous = node;
    }
    switch (r.way.kind) {
      case FootWayKind::kSidewalk: ++g.stats.sidewalk_ways; break;
      case FootWayKind::kCrossing: ++g.stats.crossing_ways; break;
      case FootWayKind::kSteps: ++g.stats.steps_ways; break;
      default: break;
    }
    g.ways.push_back(std::move(r.way));
  }
  for (const FootNode& n : g.nodes) {
    if (!n.crossing.is_crossing()) continue;
    ++g.stats.crossing_nodes;
    if (n.crossing.tactile_paving.value_or(false)) ++g.stats.tactile_crossings;
    if (n.crossing.control == CrossingControl::kTrafficSignals) ++g.stats.signal_crossings;
  }
  g.offsets.assign(g.nodes.size() + 1, 0);
  for (const FootEdge& e : g.edges) {
    ++g.offsets[e.a + 1];
    ++g.offsets[e.b + 1];
  }
  for (std::size_t i = 1; i < g.offsets.size(); ++i) g.offsets[i] += g.offsets[i - 1];
  g.adjacency.resize(g.offsets.back());
  std::vector<std::uint32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (std::uint32_t e = 0; e < g.edges.size(); ++e) {
    g.adjacency[fill[g.edges[e].a]++] = e;
    g.adjacency[fill[g.edges[e].b]++] = e;
  }
  return g;
}

FootGraph read(osmium::io::File file, const std::string& name) {
  const auto t0 = std::chrono::steady_clock::now();
  Collector collector;
  try {
    using Index = osmium::index::map::FlexMem<osmium::unsigned_object_id_type, osmium::Location>;
    Index locations;
    osmium::handler::NodeLocationsForWays<Index> location_handler{locations};
    location_handler.ignore_errors();  // a way node outside an extract: counted, the way split there
    osmium::io::Reader reader{file, osmium::osm_entity_bits::node | osmium::osm_entity_bits::way};
    osmium::apply(reader, location_handler, collector);
    reader.close();
  } catch (const std::exception& e) {
    throw IoError(name, std::string("not a readable OSM file: ") + e.what());
  }
  FootGraph g = build(collector);
  g.stats.load_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return g;
}

}  // namespace

std::string_view tag_value(const OsmTags& tags, std::string_view key) {
  for (const auto& [k, v] : tags) {
    if (k == key) return v;
  }
  return {};
}

const char* to_string(FootWayKind kind) {
  switch (kind) {
    case FootWayKind::kSidewalk: return "sidewalk";
    case FootWayKind::kCrossing: return "crossing";
    case FootWayKind::kFootway: return "footway";
    case FootWayKind::kSteps: return "steps";
    case FootWayKind::kRoadWithSidewalk: return "road_with_sidewalk";
    case FootWayKind::kRoad: return "road";
  }
  return "?";
}

const char* to_string(CrossingControl control) {
  switch (control) {
    case CrossingControl::kNone: return "none";
    case CrossingControl::kTrafficSignals: return "traffic_signals";
    case CrossingControl::kMarked: return "marked";
    case CrossingControl::kUncontrolled: return "uncontrolled";
    case CrossingControl::kUnmarked: return "unmarked";
    case CrossingControl::kUnknown: return "unknown";
  }
  return "?";
}

CrossingInfo crossing_from_tags(const OsmTags& tags, bool is_way) {
  CrossingInfo c;
  const std::string_view crossing = tag_value(tags, "crossing");
  bool is_crossing = false;
  if (is_way) {
    is_crossing = tag_value(tags, "footway") == "crossing" || tag_value(tags, "path") == "crossing" ||
                  tag_value(tags, "cycleway") == "crossing";
  } else {
    is_crossing = tag_value(tags, "highway") == "crossing" || (!crossing.empty() && crossing != "no");
  }
  if (!is_crossing || crossing == "no") return c;
  const std::string_view signals = tag_value(tags, "crossing:signals");
  const std::string_view ref = tag_value(tags, "crossing_ref");
  const std::string_view markings = tag_value(tags, "crossing:markings");
  if (crossing == "traffic_signals" || signals == "yes" || one_of(ref, {"pelican", "toucan", "puffin", "pegasus"})) {
    c.control = CrossingControl::kTrafficSignals;
  } else if (crossing == "uncontrolled") {  // the explicit crossing=* value before crossing:markings
    c.control = CrossingControl::kUncontrolled;
  } else if (crossing == "unmarked") {
    c.control = CrossingControl::kUnmarked;
  } else if (one_of(crossing, {"zebra", "marked"}) || ref == "zebra" || (!markings.empty() && markings != "no")) {
    c.control = CrossingControl::kMarked;
  } else if (markings == "no") {
    c.control = CrossingControl::kUnmarked;
  } else {
    c.control = CrossingControl::kUnknown;
  }
  const std::string_view tactile = tag_value(tags, "tactile_paving");
  if (!tactile.empty()) c.tactile_paving = tactile != "no";
  c.kerb = std::string(tag_value(tags, "kerb"));
  c.island = crossing == "island" || tag_value(tags, "crossing:island") == "yes";
  return c;
}

CrossingInfo merge_crossings(const CrossingInfo& a, const CrossingInfo& b) {
  CrossingInfo m = rank(a.control) >= rank(b.control) ? a : b;
  if (a.tactile_paving || b.tactile_paving) m.tactile_paving = a.tactile_paving.value_or(false) || b.tactile_paving.value_or(false);
  if (m.kerb.empty()) m.kerb = a.kerb.empty() ? b.kerb : a.kerb;
  m.island = a.island || b.island;
  return m;
}

std::optional<FootWayKind> classify_foot_way(const OsmTags& tags) {
  const std::string_view highway = tag_value(tags, "highway");
  if (highway.empty()) return std::nullopt;
  const std::string_view foot = tag_value(tags, "foot");
  const std::string_view access = tag_value(tags, "access");
  const bool foot_yes = one_of(foot, {"yes", "designated", "permissive", "official"});
  // foot=* decides first; use_sidepath: walk the separately mapped sidewalk instead.
  if (one_of(foot, {"no", "private", "use_sidepath"})) return std::nullopt;
  if (!foot_yes && one_of(access, {"no", "private"})) return std::nullopt;
  if (one_of(highway, {"construction", "proposed", "abandoned", "disused", "raceway", "bus_guideway", "razed"})) {
    return std::nullopt;
  }
  const std::string_view footway = tag_value(tags, "footway");
  const std::string_view path = tag_value(tags, "path");
  if (one_of(highway, {"footway", "path", "pedestrian", "living_street", "corridor", "bridleway", "platform", "track",
                       "cycleway"})) {
    if (highway == "cycleway" && !foot_yes && footway != "sidewalk" && footway != "crossing") return std::nullopt;
    if (footway == "sidewalk" || path == "sidewalk") return FootWayKind::kSidewalk;
    if (footway == "crossing" || path == "crossing" || tag_value(tags, "cycleway") == "crossing") {
      return FootWayKind::kCrossing;
    }
    return FootWayKind::kFootway;
  }
  if (highway == "steps") return FootWayKind::kSteps;
  const bool motor_only = one_of(highway, {"motorway", "motorway_link", "trunk", "trunk_link"});
  const bool road = one_of(highway, {"residential", "service", "unclassified", "tertiary", "tertiary_link", "secondary",
                                     "secondary_link", "primary", "primary_link", "road"});
  if (!(road || (motor_only && foot_yes))) return std::nullopt;
  const std::string_view sidewalk = tag_value(tags, "sidewalk");
  const bool has_sidewalk = one_of(sidewalk, {"both", "left", "right", "yes"}) ||
                            tag_value(tags, "sidewalk:both") == "yes" || tag_value(tags, "sidewalk:left") == "yes" ||
                            tag_value(tags, "sidewalk:right") == "yes";
  return has_sidewalk ? FootWayKind::kRoadWithSidewalk : FootWayKind::kRoad;
}

double ellipsoidal_length_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  constexpr double a = 6378137.0;          // WGS84
  constexpr double e2 = 6.69437999014e-3;
  const double phi = 0.5 * (lat1_deg + lat2_deg) * kDeg;
  const double w = 1.0 - e2 * std::sin(phi) * std::sin(phi);
  const double meridian = a * (1.0 - e2) / (w * std::sqrt(w));
  const double normal = a / std::sqrt(w);
  return std::hypot((lat2_deg - lat1_deg) * kDeg * meridian, (lon2_deg - lon1_deg) * kDeg * normal * std::cos(phi));
}

double haversine_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg) {
  constexpr double kRadius = 6371008.8;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double dlat = (lat2_deg - lat1_deg) * kDeg;
  const double dlon = (lon2_deg - lon1_deg) * kDeg;
  const double s = std::sin(dlat / 2) * std::sin(dlat / 2) +
                   std::cos(lat1_deg * kDeg) * std::cos(lat2_deg * kDeg) * std::sin(dlon / 2) * std::sin(dlon / 2);
  return 2.0 * kRadius * std::asin(std::min(1.0, std::sqrt(s)));
}

FootGraph load_osm_foot_graph(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path.string(), "no such OSM file");
  return read(osmium::io::File{path.string()}, path.string());
}

FootGraph parse_osm_foot_graph(std::string_view data, const std::string& format, const std::string& name) {
  if (format != "osm" && format != "pbf") throw IoError(name, "OSM format must be osm or pbf, not '" + format + "'");
  if (data.empty()) throw IoError(name, "empty OSM data");
  return read(osmium::io::File{data.data(), data.size(), format}, name);
}

}  // namespace navaid::planning
