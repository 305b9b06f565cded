// End-to-end tests of `navaid plan`: the real Willow office map and the real geb079 OctoMap,
// scenario ground truth with a directional subgoal, and every bad input with its message.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

nlohmann::json plan_json(const fs::path& out) { return nlohmann::json::parse(read_text(out / "plan.json")); }

TEST(PlanCli, AStarAndDirectionAStarOnTheRealWillowOfficeMap) {
  NAVAID_REQUIRE_SHARED_DATA();
  const ScratchDir dir("plan_cli_willow");
  const std::string map = (navaid::testing::shared_data_dir() / "ros-map-willow/willow-full-0.05.yaml").string();
  const auto astar = navaid_cli("plan --map '" + map + "' --planner astar --start 10,10,0 --goal 35,40 --out '" +
                                (dir / "astar").string() + "'");
  ASSERT_EQ(astar.status, 0) << astar.output;
  const nlohmann::json a = plan_json(dir / "astar");
  EXPECT_EQ(a["status"], "found");
  EXPECT_EQ(a["planner"], "astar");
  // Through the building's corridors: longer than the straight line (39.05 m), not absurdly.
  EXPECT_GT(a["length_m"].get<double>(), std::hypot(25.0, 30.0));
  EXPECT_LT(a["length_m"].get<double>(), 80.0);
  EXPECT_GT(a["nodes_expanded"].get<int>(), 1000);
  EXPECT_TRUE(fs::exists(dir / "astar" / "plan.png"));
  const auto& path = a["path"];
  EXPECT_NEAR(path.front()[0].get<double>(), 10.025, 1e-9);
  EXPECT_NEAR(path.back()[1].get<double>(), 40.025, 1e-9);

  const auto direction = navaid_cli("plan --map '" + map + "' --planner direction-astar --start 10,10,0 --direction 90 --out '" +
                                    (dir / "dir").string() + "'");
  ASSERT_EQ(direction.status, 0) << direction.output;
  const nlohmann::json d = plan_json(dir / "dir");
  EXPECT_EQ(d["status"], "found");
  EXPECT_LE(d["length_m"].get<double>(), 20.0);  // inside the 10 m window
}

TEST(PlanCli, AStarAndDirectionAStarAlongTheRealGeb079Corridor) {
  NAVAID_REQUIRE_SHARED_DATA();
  const ScratchDir dir("plan_cli_geb079");
  const std::string map = (navaid::testing::shared_data_dir() / "octomap-geb079/geb079.bt").string();
  const auto run = navaid_cli("plan --map '" + map + "' --start 1,-0.1,0 --goal 9,-0.1 --set mapping.collision.min_relative_height_m=-1.32 --out '" +
                              dir.path().string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json j = plan_json(dir.path());
  EXPECT_EQ(j["status"], "found");
  EXPECT_NEAR(j["length_m"].get<double>(), 8.0, 0.5);  // straight down the corridor
  EXPECT_NE(j["map"].get<std::string>().find("OctoMap"), std::string::npos);
  // Direction A* down the same corridor (+x): a path inside the 10 m window heading east.
  const fs::path direction_out = dir / "direction";
  const auto direction = navaid_cli("plan --map '" + map + "' --planner direction-astar --start 1,-0.1,0 --direction 0 " +
                                    "--set mapping.collision.min_relative_height_m=-1.32 --out '" + direction_out.string() + "'");
  ASSERT_EQ(direction.status, 0) << direction.output;
  const nlohmann::json d = plan_json(direction_out);
  EXPECT_EQ(d["status"], "found");
  EXPECT_GT(d["path"].back()[0].get<double>(), 4.0);
}

TEST(PlanCli, WalkingPathGeneratorOnTheRealWillowMapAndTheGeb079Corridor) {
  NAVAID_REQUIRE_SHARED_DATA();
  const ScratchDir dir("plan_cli_wpg");
  const std::string willow = (navaid::testing::shared_data_dir() / "ros-map-willow/willow-full-0.05.yaml").string();
  // From the west corridor to a room in the north-east: footsteps all the way.
  const auto wpg = navaid_cli("plan --map '" + willow + "' --planner wpg --start 5.6,20,90 --goal 35,40 --out '" +
                              (dir / "wpg").string() + "'");
  ASSERT_EQ(wpg.status, 0) << wpg.output;
  const nlohmann::json w = plan_json(dir / "wpg");
  EXPECT_EQ(w["status"], "found");
  EXPECT_EQ(w["planner"], "wpg");
  EXPECT_GT(w["length_m"].get<double>(), std::hypot(29.4, 20.0));
  EXPECT_LT(w["length_m"].get<double>(), 90.0);
  EXPECT_EQ(w["footsteps"].size(), w["path"].size());
  EXPECT_EQ(w["path"][0].size(), 3U);  // x, y and the walking direction
  const auto astar = navaid_cli("plan --map '" + willow + "' --planner astar --start 5.6,20,90 --goal 35,40 " +
                                "--set planning.grid.base_clearance_m=0.3 --out '" + (dir / "astar").string() + "'");
  ASSERT_EQ(astar.status, 0) << astar.output;
  // Footsteps of half a metre against cells of 5 cm: far fewer nodes.
  EXPECT_LT(10 * w["nodes_expanded"].get<int>(), plan_json(dir / "astar")["nodes_expanded"].get<int>());

  // Re-planning inside the 10 m range toward a direction.
  const auto dir90 = navaid_cli("plan --map '" + willow + "' --planner wpg --start 5.6,20,90 --direction 90 " +
                                "--set planning.wpg.horizon_m=10 --out '" + (dir / "dir").string() + "'");
  ASSERT_EQ(dir90.status, 0) << dir90.output;
  const nlohmann::json d = plan_json(dir / "dir");
  const auto& end = d["path"].back();
  EXPECT_GE(std::hypot(end[0].get<double>() - 5.6, end[1].get<double>() - 20.0), 10.0);
  EXPECT_GT(end[1].get<double>(), 27.0);  // northward

  const std::string geb079 = (navaid::testing::shared_data_dir() / "octomap-geb079/geb079.bt").string();
  const auto corridor = navaid_cli("plan --map '" + geb079 + "' --planner wpg --start 1,-0.1,0 --goal 9,-0.1 " +
                                   "--set mapping.collision.min_relative_height_m=-1.32 --out '" + (dir / "geb").string() + "'");
  ASSERT_EQ(corridor.status, 0) << corridor.output;
  EXPECT_NEAR(plan_json(dir / "geb")["length_m"].get<double>(), 8.0, 0.6);
  // Without the ESDF clearance a start in the wall is refused with its reason.
  const auto in_wall = navaid_cli("plan --map scenario:office1 --planner wpg --start 2,2,0 --goal 30,30 --out '" +
                                  (dir / "blocked").string() + "'");
  EXPECT_EQ(in_wall.status, 4) << in_wall.output;
  EXPECT_EQ(plan_json(dir / "blocked")["reason"], "start-blocked");
}

TEST(PlanCli, ReasonsAndErrors) {
  const ScratchDir dir("plan_cli_errors");
  const std::string out = " --out '" + dir.path().string() + "'";
  // On a desk in office1: a plan without a path, exit 4, the reason in the JSON.
  const auto blocked = navaid_cli("plan --map scenario:office1 --start 2,2,0 --goal 30,30" + out);
  EXPECT_EQ(blocked.status, 4) << blocked.output;
  EXPECT_EQ(plan_json(dir.path())["reason"], "start-blocked");
  const auto off = navaid_cli("plan --map scenario:office1 --start 18.5,5,90 --goal 300,30" + out);
  EXPECT_EQ(off.status, 4) << off.output;
  EXPECT_EQ(plan_json(dir.path())["reason"], "off-map");
  EXPECT_NE(off.output.find("goal (300.00, 30.00) is off the map"), std::string::npos) << off.output;

  const auto unknown_planner = navaid_cli("plan --map scenario:office1 --planner rrt --start 1,1,0 --goal 2,2" + out);
  EXPECT_EQ(unknown_planner.status, 2);
  EXPECT_NE(unknown_planner.output.find("unknown planner 'rrt'"), std::string::npos) << unknown_planner.output;
  const auto no_map = navaid_cli("plan --map /nonexistent/map.yaml --start 1,1,0 --goal 2,2" + out);
  EXPECT_EQ(no_map.status, 2);
  EXPECT_NE(no_map.output.find("/nonexistent/map.yaml"), std::string::npos) << no_map.output;
  const auto both = navaid_cli("plan --map scenario:office1 --start 1,1,0 --goal 2,2 --direction 10" + out);
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.output.find("exactly one of --goal"), std::string::npos) << both.output;
  const auto bad_start = navaid_cli("plan --map scenario:office1 --start 1,1 --goal 2,2" + out);
  EXPECT_EQ(bad_start.status, 2);
  const auto bad_key = navaid_cli("plan --map scenario:office1 --start 18.5,5,90 --goal 30,35 --set planning.grid.lenght_weight=2" + out);
  EXPECT_EQ(bad_key.status, 2);
  EXPECT_NE(bad_key.output.find("lenght_weight"), std::string::npos) << bad_key.output;
  const auto bad_scenario = navaid_cli("plan --map scenario:mars --start 1,1,0 --goal 2,2" + out);
  EXPECT_EQ(bad_scenario.status, 2);
}

}  // namespace
