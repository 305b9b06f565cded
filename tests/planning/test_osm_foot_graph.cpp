// The foot graph's tag rules (docs/routing.md, one test per rule), the hand-made OSM fixture, every
// real extract in ../shared/data/osm, and broken inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/planning/osm_foot_graph.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace navaid::planning;

namespace {

const fs::path kFixture = fs::path(NAVAID_SOURCE_DIR) / "tests/planning/fixtures/foot_street.osm";

std::optional<FootWayKind> kind(const OsmTags& tags) { return classify_foot_way(tags); }

// ---- Walkability rules ----

TEST(FootRules, FootwaysPathsPedestrianAndLivingStreetsAreFootways) {
  for (const char* h : {"footway", "path", "pedestrian", "living_street", "track", "corridor", "bridleway", "platform"}) {
    EXPECT_EQ(kind({{"highway", h}}), FootWayKind::kFootway) << h;
  }
}

TEST(FootRules, SidewalkAndCrossingFootways) {
  EXPECT_EQ(kind({{"highway", "footway"}, {"footway", "sidewalk"}}), FootWayKind::kSidewalk);
  EXPECT_EQ(kind({{"highway", "path"}, {"path", "sidewalk"}}), FootWayKind::kSidewalk);
  EXPECT_EQ(kind({{"highway", "footway"}, {"footway", "crossing"}}), FootWayKind::kCrossing);
  EXPECT_EQ(kind({{"highway", "cycleway"}, {"footway", "crossing"}}), FootWayKind::kCrossing);
}

TEST(FootRules, StepsAreSteps) { EXPECT_EQ(kind({{"highway", "steps"}}), FootWayKind::kSteps); }

TEST(FootRules, RoadsAreWalkableWithOrWithoutSidewalk) {
  for (const char* h : {"residential", "service", "unclassified", "tertiary", "secondary", "primary", "road"}) {
    EXPECT_EQ(kind({{"highway", h}}), FootWayKind::kRoad) << h;
  }
  for (const char* s : {"both", "left", "right", "yes"}) {
    EXPECT_EQ(kind({{"highway", "primary"}, {"sidewalk", s}}), FootWayKind::kRoadWithSidewalk) << s;
  }
  EXPECT_EQ(kind({{"highway", "primary"}, {"sidewalk:left", "yes"}}), FootWayKind::kRoadWithSidewalk);
  EXPECT_EQ(kind({{"highway", "primary"}, {"sidewalk", "no"}}), FootWayKind::kRoad);
  EXPECT_EQ(kind({{"highway", "primary"}, {"sidewalk", "separate"}}), FootWayKind::kRoad);
}

TEST(FootRules, MotorwaysAndTrunksOnlyWithFootYes) {
  for (const char* h : {"motorway", "motorway_link", "trunk", "trunk_link"}) {
    EXPECT_FALSE(kind({{"highway", h}})) << h;
    EXPECT_FALSE(kind({{"highway", h}, {"sidewalk", "both"}})) << h;
    EXPECT_EQ(kind({{"highway", h}, {"foot", "yes"}}), FootWayKind::kRoad) << h;
  }
}

TEST(FootRules, AccessNoOrPrivateExcludesUnlessFootAllows) {
  EXPECT_FALSE(kind({{"highway", "footway"}, {"access", "private"}}));
  EXPECT_FALSE(kind({{"highway", "service"}, {"access", "no"}}));
  EXPECT_EQ(kind({{"highway", "service"}, {"access", "no"}, {"foot", "yes"}}), FootWayKind::kRoad);
  EXPECT_EQ(kind({{"highway", "service"}, {"access", "private"}, {"foot", "designated"}}), FootWayKind::kRoad);
}

TEST(FootRules, FootNoPrivateOrUseSidepathExcludes) {
  for (const char* f : {"no", "private", "use_sidepath"}) {
    EXPECT_FALSE(kind({{"highway", "residential"}, {"foot", f}})) << f;
    EXPECT_FALSE(kind({{"highway", "footway"}, {"foot", f}, {"access", "yes"}})) << f;
  }
}

TEST(FootRules, CyclewaysOnlyWithFootAllowed) {
  EXPECT_FALSE(kind({{"highway", "cycleway"}}));
  EXPECT_EQ(kind({{"highway", "cycleway"}, {"foot", "designated"}}), FootWayKind::kFootway);
}

TEST(FootRules, NotWalkable) {
  EXPECT_FALSE(kind({}));
  EXPECT_FALSE(kind({{"building", "yes"}}));
  for (const char* h : {"construction", "proposed", "abandoned", "raceway", "bus_guideway", "bus_stop"}) {
    EXPECT_FALSE(kind({{"highway", h}, {"foot", "yes"}})) << h;
  }
}

// ---- Crossing rules ----

TEST(CrossingRules, NodeControlFromCrossingTags) {
  const auto control = [](const OsmTags& t) { return crossing_from_tags(t, false).control; };
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "traffic_signals"}}), CrossingControl::kTrafficSignals);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing:signals", "yes"}}), CrossingControl::kTrafficSignals);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing_ref", "pelican"}}), CrossingControl::kTrafficSignals);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "zebra"}}), CrossingControl::kMarked);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "marked"}}), CrossingControl::kMarked);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing_ref", "zebra"}}), CrossingControl::kMarked);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "uncontrolled"}}), CrossingControl::kUncontrolled);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "unmarked"}}), CrossingControl::kUnmarked);
  EXPECT_EQ(control({{"highway", "crossing"}}), CrossingControl::kUnknown);
  // The explicit crossing=* value wins over crossing:markings (the scenario export's zebra markings).
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "uncontrolled"}, {"crossing:markings", "zebra"}}),
            CrossingControl::kUncontrolled);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing:markings", "zebra"}}), CrossingControl::kMarked);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing:markings", "no"}}), CrossingControl::kUnmarked);
  // crossing=* on a traffic-signals node (the road node of a signalled crossing).
  EXPECT_EQ(control({{"highway", "traffic_signals"}, {"crossing", "traffic_signals"}}), CrossingControl::kTrafficSignals);
  EXPECT_EQ(control({{"highway", "traffic_signals"}}), CrossingControl::kNone);
  EXPECT_EQ(control({{"highway", "crossing"}, {"crossing", "no"}}), CrossingControl::kNone);
  EXPECT_EQ(control({{"amenity", "bench"}}), CrossingControl::kNone);
}

TEST(CrossingRules, TactilePavingKerbAndIsland) {
  const CrossingInfo yes = crossing_from_tags(
      {{"highway", "crossing"}, {"crossing", "island"}, {"tactile_paving", "yes"}, {"kerb", "lowered"}}, false);
  EXPECT_EQ(yes.tactile_paving, std::optional<bool>(true));
  EXPECT_EQ(yes.kerb, "lowered");
  EXPECT_TRUE(yes.island);
  const CrossingInfo no = crossing_from_tags({{"highway", "crossing"}, {"tactile_paving", "no"}}, false);
  EXPECT_EQ(no.tactile_paving, std::optional<bool>(false));
  EXPECT_FALSE(crossing_from_tags({{"highway", "crossing"}}, false).tactile_paving.has_value());
}

TEST(CrossingRules, CrossingWaysAndMerging) {
  EXPECT_TRUE(crossing_from_tags({{"highway", "footway"}, {"footway", "crossing"}}, true).is_crossing());
  EXPECT_FALSE(crossing_from_tags({{"highway", "footway"}, {"footway", "sidewalk"}}, true).is_crossing());
  CrossingInfo a;
  a.control = CrossingControl::kUnknown;
  CrossingInfo b;
  b.control = CrossingControl::kTrafficSignals;
  b.tactile_paving = true;
  const CrossingInfo m = merge_crossings(a, b);
  EXPECT_EQ(m.control, CrossingControl::kTrafficSignals);
  EXPECT_EQ(m.tactile_paving, std::optional<bool>(true));
}

// ---- The hand-made fixture ----

TEST(OsmFootGraph, HandMadeFixtureCounts) {
  const FootGraph g = load_osm_foot_graph(kFixture);
  EXPECT_EQ(g.stats.walkable_ways, 11U);
  EXPECT_EQ(g.stats.excluded_ways, 2U);  // the motorway and the private footway
  EXPECT_EQ(g.stats.sidewalk_ways, 3U);
  EXPECT_EQ(g.stats.crossing_ways, 2U);
  EXPECT_EQ(g.stats.steps_ways, 1U);
  EXPECT_EQ(g.stats.crossing_nodes, 2U);
  EXPECT_EQ(g.stats.signal_crossings, 1U);
  EXPECT_EQ(g.stats.tactile_crossings, 1U);
  EXPECT_EQ(g.stats.missing_locations, 0U);
  ASSERT_EQ(g.landmarks.size(), 1U);
  EXPECT_EQ(g.landmarks[0].name, "Café Rampe");
  EXPECT_EQ(g.landmarks[0].kind, "amenity=cafe");
  // Road 1001 has 4 edges of 50 m.
  double road = 0;
  for (const FootEdge& e : g.edges) {
    if (g.ways[e.way].osm_id == 1001) road += e.length_m;
  }
  // The fixture was laid out with 111.2 km per degree; WGS84 at 48 N has 111.526 km per degree of
  // longitude / cos(lat) (prime-vertical radius 6389.96 km): 200.59 m.
  EXPECT_NEAR(road, 200.0 * 6389960.0 * 3.14159265358979 / 180.0 / 111200.0, 0.02);
  // The signalled crossing way took its middle node's control and tactile paving.
  for (const FootWay& w : g.ways) {
    if (w.osm_id == 2005) {
      EXPECT_EQ(w.crossing.control, CrossingControl::kTrafficSignals);
      EXPECT_EQ(w.crossing.tactile_paving, std::optional<bool>(true));
    }
    if (w.osm_id == 2004) {
      EXPECT_EQ(w.crossing.control, CrossingControl::kUncontrolled);
    }
    if (w.osm_id == 2001) {
      EXPECT_EQ(w.name, "Ringstrasse");
    }
  }
  // CSR adjacency: every edge appears twice.
  EXPECT_EQ(g.adjacency.size(), 2 * g.edges.size());
}

TEST(OsmFootGraph, SameFixtureFromMemory) {
  const std::string xml = navaid::testing::read_text(kFixture);
  const FootGraph g = parse_osm_foot_graph(xml, "osm");
  EXPECT_EQ(g.stats.walkable_ways, 11U);
}

TEST(OsmFootGraph, WayNodeMissingFromTheFileSplitsTheWay) {
  const std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" lat="48.0" lon="11.0"/>
 <node id="2" lat="48.0001" lon="11.0"/>
 <node id="4" lat="48.0003" lon="11.0"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><tag k="highway" v="footway"/></way>
</osm>
)";
  const FootGraph g = parse_osm_foot_graph(xml, "osm");
  EXPECT_EQ(g.stats.missing_locations, 1U);
  EXPECT_EQ(g.edges.size(), 1U);  // 1-2 only: no edge across the missing node 3
}

// ---- Broken input ----

TEST(OsmFootGraph, BrokenInputsAreIoErrors) {
  EXPECT_THROW(load_osm_foot_graph("/nonexistent/file.osm"), navaid::IoError);
  EXPECT_THROW(parse_osm_foot_graph("<osm version=\"0.6\"><node id=\"1\" lat=\"48\" lon=\"11\"></osm>", "osm"),
               navaid::IoError);
  EXPECT_THROW(parse_osm_foot_graph("this is not xml", "osm"), navaid::IoError);
  EXPECT_THROW(parse_osm_foot_graph("", "osm"), navaid::IoError);
  EXPECT_THROW(parse_osm_foot_graph("<osm/>", "json"), navaid::IoError);
}

TEST(OsmFootGraph, FileWithoutFootWaysGivesAnEmptyGraph) {
  const std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" lat="48.0" lon="11.0"/>
 <node id="2" lat="48.0001" lon="11.0"/>
 <node id="3" lat="48.0001" lon="11.0001"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="1"/><tag k="building" v="yes"/></way>
 <way id="11"><nd ref="1"/><nd ref="2"/><tag k="highway" v="motorway"/></way>
</osm>
)";
  const FootGraph g = parse_osm_foot_graph(xml, "osm");
  EXPECT_TRUE(g.empty());
  EXPECT_EQ(g.stats.osm_ways, 2U);
  EXPECT_EQ(g.stats.excluded_ways, 1U);
}

TEST(OsmFootGraph, TruncatedPbfIsAnIoError) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path pbf = navaid::testing::shared_data_dir() / "osm/paris_bss.osm.pbf";
  const std::string bytes = navaid::testing::read_text(pbf);
  ASSERT_GT(bytes.size(), 1000U);
  const navaid::testing::ScratchDir dir("osm_truncated");
  const fs::path cut = dir / "cut.osm.pbf";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(load_osm_foot_graph(cut), navaid::IoError);
  EXPECT_THROW(parse_osm_foot_graph(std::string_view(bytes).substr(0, 200), "pbf"), navaid::IoError);
  // Garbage with a .pbf name.
  const fs::path junk = dir / "junk.osm.pbf";
  std::ofstream(junk, std::ios::binary) << std::string(5000, 'x');
  EXPECT_THROW(load_osm_foot_graph(junk), navaid::IoError);
  // A truncated gzip XML.
  const fs::path gz = navaid::testing::shared_data_dir() / "osm/berlin-siegessaeule.osm.gz";
  const std::string gbytes = navaid::testing::read_text(gz);
  const fs::path gcut = dir / "cut.osm.gz";
  std::ofstream(gcut, std::ios::binary) << gbytes.substr(0, gbytes.size() / 2);
  EXPECT_THROW(load_osm_foot_graph(gcut), navaid::IoError);
}

// ---- Every real extract ----

TEST(OsmFootGraph, EveryRealExtractLoads) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path dir = navaid::testing::shared_data_dir() / "osm";
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".osm") == std::string::npos) continue;
    ++files;
    const FootGraph g = load_osm_foot_graph(entry.path());
    if (name == "melborne.osm.pbf") {
      // Valhalla's Tokyo expressway fixture: every highway=* way carries foot=no.
      EXPECT_EQ(g.stats.walkable_ways, 0U) << name;
      EXPECT_EQ(g.stats.excluded_ways, g.stats.osm_ways) << name;
      EXPECT_GT(g.stats.osm_ways, 1000U) << name;
      continue;
    }
    // Every other extract has highway=* ways a pedestrian may use (TAGS.txt).
    EXPECT_GT(g.stats.walkable_ways, 0U) << name;
    EXPECT_GT(g.edges.size(), 0U) << name;
    EXPECT_GT(g.stats.osm_nodes, 0U) << name;
    for (const FootEdge& e : g.edges) {
      ASSERT_GE(e.length_m, 0.0) << name;
      ASSERT_LT(e.length_m, 20000.0) << name;
    }
  }
  EXPECT_EQ(files, 20U);
}

TEST(OsmFootGraph, RealExtractTagsAsTagsTxtCounts) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path dir = navaid::testing::shared_data_dir() / "osm";
  // Berlin: footway=sidewalk 11 ways, footway=crossing 2, highway=steps 10 (TAGS.txt); signalled crossings.
  const FootGraph berlin = load_osm_foot_graph(dir / "berlin-siegessaeule.osm.gz");
  EXPECT_EQ(berlin.stats.sidewalk_ways, 11U);
  // footway=crossing on 2 footways (TAGS.txt) and cycleway=crossing on a cycleway open to pedestrians.
  EXPECT_EQ(berlin.stats.crossing_ways, 3U);
  EXPECT_EQ(berlin.stats.steps_ways, 10U);
  EXPECT_GE(berlin.stats.signal_crossings, 10U);
  // Paris: hundreds of crossings, many with tactile paving.
  const FootGraph paris = load_osm_foot_graph(dir / "paris_bss.osm.pbf");
  EXPECT_GT(paris.stats.crossing_nodes, 300U);
  EXPECT_GT(paris.stats.tactile_crossings, 100U);
  // bzip2 XML (West Oakland) and plain XML with an .xml suffix (Laufamholzstrasse).
  EXPECT_GT(load_osm_foot_graph(dir / "West-Oakland.osm.bz2").stats.walkable_ways, 0U);
  const FootGraph lauf = load_osm_foot_graph(dir / "Laufamholzstrasse.osm.xml");
  EXPECT_EQ(lauf.stats.steps_ways + lauf.stats.crossing_ways, 0U);
  EXPECT_GT(lauf.stats.walkable_ways, 30U);
}

}  // namespace
