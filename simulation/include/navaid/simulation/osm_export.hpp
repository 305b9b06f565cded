#pragma once
// The street scenarios (route1, route2) as OpenStreetMap data: their sidewalks, crossings, roads
// and named landmarks written as OSM XML 0.6 in the scenario's geodetic frame (W = ENU at the
// scenario's origin, GeographicLib), and the scenario's own walking route over that graph as ground
// truth for OSM routers (docs/scenarios.md, "Simulated streets as OSM").
//
// Tags (the contract OSM routers read):
//   sidewalk centre lines   highway=footway + footway=sidewalk
//   crossings               highway=footway + footway=crossing, its middle node highway=crossing +
//                           crossing=traffic_signals|uncontrolled (+ tactile_paving=yes|no when known)
//   roads                   highway=<class> + name=*
//   landmarks               nodes with name=* and amenity=* or shop=*
// Sidewalks and crossings share their end nodes, so the walkways form one graph wherever the world
// connects them.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::simulation {

using OsmTags = std::vector<std::pair<std::string, std::string>>;

enum class CrossingControl { kTrafficSignals, kUncontrolled };

/// A crossing from one sidewalk end to another (straight, its middle node carries the crossing tags).
struct StreetCrossing {
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();  ///< ends in W, each on a sidewalk line
  CrossingControl control = CrossingControl::kUncontrolled;
  std::optional<bool> tactile_paving;           ///< known: yes / no; unknown: not tagged
  std::string markings;                         ///< crossing:markings value ("zebra"), empty = untagged
  /// Height of the step between sidewalk and road at both ends (kerb=raised + kerb:height on the
  /// end nodes); unset = flush or unknown (untagged).
  std::optional<double> kerb_height_m;
};

struct StreetRoad {
  std::vector<Vec2> line;                ///< centre line in W (>= 2 points)
  std::string name;
  std::string highway = "residential";  ///< OSM highway class
  OsmTags extra;                         ///< e.g. sidewalk=separate
};

struct StreetLandmark {
  Vec2 xy = Vec2::Zero();  ///< in W
  std::string name;
  OsmTags tags;            ///< amenity=* or shop=* and any more precise tags
};

/// The street layout a street scenario is built on (in W).
struct StreetMap {
  std::vector<std::vector<Vec2>> sidewalks;  ///< centre lines (>= 2 points each)
  std::vector<StreetCrossing> crossings;
  std::vector<StreetRoad> roads;
  std::vector<StreetLandmark> landmarks;
  std::size_t goal_landmark = 0;             ///< index of the final landmark of the scenario's route
};

/// Whether a scenario has streets to export (route1, route2).
bool has_streets(std::string_view scenario_name);
/// The street layout of a street scenario. ConfigError (key "scenario") "scenario X has no streets
/// to export" for the others.
StreetMap scenario_streets(const Scenario& scenario);

struct OsmNode {
  std::int64_t id = 0;
  Vec2 xy = Vec2::Zero();        ///< in W
  double lat_deg = 0, lon_deg = 0;
  OsmTags tags;
};
struct OsmWay {
  std::int64_t id = 0;
  std::vector<std::int64_t> nodes;
  OsmTags tags;
};
/// A crossing the route uses.
struct RouteCrossing {
  std::int64_t way_id = 0, node_id = 0;  ///< the crossing way and its middle node
  std::string kind;                      ///< "traffic_signals" or "uncontrolled"
  std::string tactile_paving;            ///< "yes", "no" or "" (unknown)
  double lat_deg = 0, lon_deg = 0;
  double at_m = 0;                       ///< distance along the route to the middle node
};
/// The scenario's own walking route over the exported walkways.
struct OsmRouteTruth {
  Vec2 start_W = Vec2::Zero(), goal_W = Vec2::Zero();
  double start_lat_deg = 0, start_lon_deg = 0, goal_lat_deg = 0, goal_lon_deg = 0;
  std::vector<std::int64_t> node_ids;  ///< along the route, start to goal
  double length_m = 0;                 ///< along the walkway edges, in W
  double geodesic_length_m = 0;        ///< the same edges measured on the ellipsoid
  std::vector<RouteCrossing> crossings;
  std::string landmark_name;
  std::int64_t landmark_node_id = 0;
  double landmark_lat_deg = 0, landmark_lon_deg = 0;
};

struct OsmExport {
  std::string scenario;
  std::uint64_t seed = 0;
  GeodeticOrigin origin;
  std::vector<OsmNode> nodes;  ///< ids 1..n in order
  std::vector<OsmWay> ways;    ///< ids 1..m in order
  double min_lat = 0, min_lon = 0, max_lat = 0, max_lon = 0;
  OsmRouteTruth truth;
};

/// Builds the OSM graph of a street scenario: walkway lines are split at every point where another
/// line ends or crosses them and at the scenario path's waypoints, points closer than 1 mm share
/// one node. The truth follows the scenario's path over the walkway edges; navaid::Error when the
/// path leaves the walkways. ConfigError as scenario_streets for scenarios without streets.
OsmExport export_osm(const Scenario& scenario);

/// OSM XML 0.6 (<osm version="0.6" generator="navaid">, <bounds>, nodes, ways), lat/lon with 7
/// decimals, attribute values escaped (& < > " ').
std::string osm_xml(const OsmExport& e);
/// The route truth as JSON (osm_truth.json).
std::string osm_truth_json(const OsmExport& e);
/// Writes dir/map.osm and dir/osm_truth.json (creates dir). IoError when they cannot be written.
void write_osm_export(const OsmExport& e, const std::filesystem::path& dir);

/// XML attribute escaping of & < > " '.
std::string xml_escape(std::string_view text);

}  // namespace navaid::simulation
