#pragma once
// A pedestrian ("foot") graph from an OpenStreetMap file, for offline walking routes (eLabrador
// §III-C asks a map service for the route; navaid routes itself, see docs/routing.md).
//
// The reader (libosmium, private to the .cpp) accepts .osm, .osm.gz, .osm.bz2 and .osm.pbf files,
// or OSM XML/PBF bytes in memory. Which ways are walkable and what each way and node means for a
// blind walker (sidewalk, crossing and its control, tactile paving, kerb, steps, street name) is
// decided by the tag rules below; every rule is listed in docs/routing.md with its test.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace navaid::planning {

using OsmTags = std::vector<std::pair<std::string, std::string>>;

/// The value of `key` in `tags`, or empty.
std::string_view tag_value(const OsmTags& tags, std::string_view key);

/// What a walkable way is for the router's costs.
enum class FootWayKind {
  kSidewalk,         ///< highway=footway + footway=sidewalk (or path + footway=sidewalk)
  kCrossing,         ///< highway=footway|path|cycleway + footway=crossing (or path=crossing)
  kFootway,          ///< footway, path, pedestrian, living_street, corridor, bridleway, platform, track
  kSteps,            ///< highway=steps
  kRoadWithSidewalk, ///< a road with sidewalk=both|left|right|yes (or sidewalk:*=yes)
  kRoad,             ///< a road without a (mapped-on-it) sidewalk
};
const char* to_string(FootWayKind kind);

enum class CrossingControl {
  kNone,            ///< not a crossing
  kTrafficSignals,  ///< crossing=traffic_signals, crossing:signals=yes, crossing_ref=pelican|toucan|...
  kMarked,          ///< crossing=zebra|marked, crossing_ref=zebra, crossing:markings=yes|zebra|...
  kUncontrolled,    ///< crossing=uncontrolled (marked, no signals)
  kUnmarked,        ///< crossing=unmarked|no, crossing:markings=no
  kUnknown,         ///< a crossing whose control is not tagged
};
const char* to_string(CrossingControl control);

struct CrossingInfo {
  CrossingControl control = CrossingControl::kNone;
  std::optional<bool> tactile_paving;  ///< tactile_paving=yes|no (anything but "no" counts as yes)
  std::string kerb;                    ///< kerb=* (lowered, flush, raised, ...), empty when untagged
  bool island = false;                 ///< crossing=island or crossing:island=yes
  bool is_crossing() const { return control != CrossingControl::kNone; }
};

/// The crossing a node or way describes (control kNone when it describes none). Node rule:
/// highway=crossing, or crossing=* on highway=traffic_signals; way rule: footway=crossing.
CrossingInfo crossing_from_tags(const OsmTags& tags, bool is_way);
/// Combines what a crossing way and its crossing nodes say: the safer known control wins (signals
/// over marked over uncontrolled over unmarked over unknown), tactile paving yes over no.
CrossingInfo merge_crossings(const CrossingInfo& a, const CrossingInfo& b);

/// The walkability rules for one way's tags: nullopt when a pedestrian may not or cannot walk it.
std::optional<FootWayKind> classify_foot_way(const OsmTags& tags);

struct FootWay {
  std::int64_t osm_id = 0;
  FootWayKind kind = FootWayKind::kFootway;
  std::string highway;  ///< the highway=* value
  std::string name;     ///< name=* (or ref=*), empty when untagged
  CrossingInfo crossing;  ///< for kCrossing ways: the way's tags merged with its crossing nodes'
  bool is_road() const { return kind == FootWayKind::kRoad || kind == FootWayKind::kRoadWithSidewalk; }
};

struct FootNode {
  std::int64_t osm_id = 0;
  double lat_deg = 0, lon_deg = 0;
  CrossingInfo crossing;  ///< a crossing node (highway=crossing, ...), else control kNone
};

struct FootEdge {
  std::uint32_t a = 0, b = 0;  ///< node indices
  std::uint32_t way = 0;       ///< index into FootGraph::ways
  double length_m = 0;         ///< WGS84 length (ellipsoidal_length_m)
};

/// A named point of interest for the narration: name=* with amenity=*, shop=* or tourism=*.
struct Landmark {
  std::int64_t osm_id = 0;
  double lat_deg = 0, lon_deg = 0;
  std::string name;
  std::string kind;  ///< "amenity=cafe", "shop=bakery", ...
};

struct FootGraphStats {
  std::size_t osm_nodes = 0, osm_ways = 0;  ///< read from the file
  std::size_t walkable_ways = 0;            ///< ways kept by classify_foot_way
  std::size_t excluded_ways = 0;            ///< highway=* ways rejected by the rules
  std::size_t missing_locations = 0;        ///< way node references without a node in the file
  std::size_t sidewalk_ways = 0, crossing_ways = 0, steps_ways = 0;
  std::size_t crossing_nodes = 0, tactile_crossings = 0, signal_crossings = 0;
  double load_time_s = 0;
};

struct FootGraph {
  std::vector<FootNode> nodes;
  std::vector<FootEdge> edges;
  std::vector<FootWay> ways;
  std::vector<Landmark> landmarks;
  /// Adjacency in CSR form: edges of node n are adjacency[offsets[n] .. offsets[n+1]) (edge indices).
  std::vector<std::uint32_t> offsets, adjacency;
  FootGraphStats stats;

  bool empty() const { return edges.empty(); }
  /// The other end of edge e seen from node n.
  std::uint32_t other(std::uint32_t e, std::uint32_t n) const { return edges[e].a == n ? edges[e].b : edges[e].a; }
};

/// Reads an OSM file (format from the suffix: .osm, .osm.gz, .osm.bz2, .osm.pbf, .pbf, .xml).
/// Throws IoError (naming the file) when it is missing, unreadable or broken (bad XML, truncated PBF).
/// A file without walkable ways gives an empty graph (stats tell why), not an error.
FootGraph load_osm_foot_graph(const std::filesystem::path& path);
/// The same from bytes in memory; `format` is "osm" (XML) or "pbf". `name` names it in errors.
FootGraph parse_osm_foot_graph(std::string_view data, const std::string& format, const std::string& name = "<memory>");

/// Length [m] of a short segment on the WGS84 ellipsoid: north and east offsets with the meridian
/// and prime-vertical radii of curvature at the mean latitude (mm-accurate for edges up to ~1 km).
double ellipsoidal_length_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg);
/// Great-circle distance [m] on the mean-radius sphere (6371008.8 m).
double haversine_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg);

}  // namespace navaid::planning
