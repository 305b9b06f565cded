// End-to-end tests of `navaid rumble`: a short simulated cane walk down the corridor, mapped with
// the obstacle pipeline by `navaid map`, then FICF and CACF on its obstacle_scan.csv; known answers
// on a hand-written scan file; and the errors (function, corrupt file, keys).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

std::vector<std::vector<std::string>> read_csv(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (!line.empty() && line.back() == ',') f.emplace_back();
    rows.push_back(f);
  }
  return rows;
}

/// Table 2.1 as the thesis's wii_haptic (D.5) decides it, written out again here.
std::string table_2_1(double f, double l, double r, double forward_threshold, double left_right_threshold) {
  if (!(f > forward_threshold)) return "off";
  if (std::abs(l - r) <= 1e-9 * std::max({1.0, l, r})) return "both";
  if (l < r && l < left_right_threshold) return "left";
  if (r < l && r < left_right_threshold) return "right";
  return "both";
}

class RumbleCli : public ::testing::Test {
 protected:
  // 3 s of the corridor with the cane rig at 160x120, 5 Hz, mapped from ground truth with the
  // obstacle pipeline on (once for all the suite's test processes).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("rumble_cli");
    inputs_ = navaid::testing::shared_cli_fixture(
        "rumble-walk", {"simulate --scenario corridor --mount cane --seed 3 --threads 1 --out {dir}/walk"
                        " --set duration=3 --set sensor.camera.resolution=[160,120] --set sensor.camera.rate=5",
                        "map --recording {dir}/walk --poses groundtruth --out {dir}/map"
                        " --set mapping.obstacles.enabled=true --png-every 0 --no-quality"});
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static fs::path input(const std::string& name) { return inputs_ / name; }
  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};

std::unique_ptr<ScratchDir> RumbleCli::dir_;
fs::path RumbleCli::inputs_;

TEST_F(RumbleCli, FicfAndCacfOnTheObstacleScansOfASimulatedCaneWalk) {
  const auto scans = read_csv(input("map") / "obstacle_scan.csv");
  ASSERT_GT(scans.size(), 5u);  // header + one row per mapped frame
  for (const auto& [function, tf, tlr] :
       {std::tuple<std::string, double, double>{"ficf", 3.0, 6.0}, std::tuple<std::string, double, double>{"cacf", 3.8, 7.0}}) {
    const fs::path out = path("rumble-" + function);
    const auto r = navaid_cli("rumble --scans '" + (input("map") / "obstacle_scan.csv").string() + "' --function " +
                              function + " --out '" + out.string() + "'");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("state changes (rumble signals):"), std::string::npos) << r.output;
    const auto rows = read_csv(out / "rumble.csv");
    ASSERT_EQ(rows.size(), scans.size()) << function;
    EXPECT_EQ(rows[0], (std::vector<std::string>{"t_ns", "C_F", "C_L", "C_R", "state"}));
    std::map<std::string, std::size_t> count;
    std::size_t changes = 0, with_cost = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
      ASSERT_EQ(rows[i].size(), 5u) << i;
      EXPECT_EQ(rows[i][0], scans[i][0]) << "row " << i << ": the scan's time";
      const double f = std::stod(rows[i][1]), l = std::stod(rows[i][2]), rr = std::stod(rows[i][3]);
      EXPECT_GE(f, 0.0);
      EXPECT_GE(l, 0.0);
      EXPECT_GE(rr, 0.0);
      with_cost += f + l + rr > 0.0;
      EXPECT_EQ(rows[i][4], table_2_1(f, l, rr, tf, tlr)) << function << " row " << i;
      ++count[rows[i][4]];
      if (i > 1 && rows[i][4] != rows[i - 1][4]) ++changes;
    }
    EXPECT_GT(with_cost, 0u) << function << ": the corridor's walls and stations are in view";
    const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["function"], function);
    EXPECT_EQ(s["forward_threshold"].get<double>(), tf);
    EXPECT_EQ(s["left_right_threshold"].get<double>(), tlr);
    EXPECT_EQ(s["scans"].get<std::size_t>(), rows.size() - 1);
    EXPECT_EQ(s["state_changes"].get<std::size_t>(), changes);
    for (const char* state : {"off", "left", "right", "both"})
      EXPECT_EQ(s["states"][state]["scans"].get<std::size_t>(), count[state]) << state;
  }
}

// The rumble states become the BYU remotes' patterns through navaid cues: every state change on
// the timeline is a new pattern (left, right or both remotes), off switches them off.
TEST_F(RumbleCli, ItsGuidanceTimelineDrivesTheRumbleRemotes) {
  const fs::path out = path("rumble-cues");
  const auto r = navaid_cli("rumble --function ficf --scans '" + (input("map") / "obstacle_scan.csv").string() + "' --out '" +
                            out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto states = read_csv(out / "rumble.csv");
  const auto timeline = read_csv(out / "guidance_timeline.csv");
  ASSERT_EQ(timeline.size(), states.size());
  for (std::size_t i = 1; i < timeline.size(); ++i) EXPECT_EQ(timeline[i][7], states[i][4]) << i;
  const auto c = navaid_cli("cues --guidance '" + (out / "guidance_timeline.csv").string() +
                            "' --device rumble --speech text --no-figure --out '" + (out / "cues").string() + "'");
  ASSERT_EQ(c.status, 0) << c.output;
  std::size_t changes = 0, on_changes = 0;
  for (std::size_t i = 2; i < states.size(); ++i) {
    if (states[i][4] == states[i - 1][4]) continue;
    ++changes;
    on_changes += states[i][4] != "off";
  }
  const auto s = nlohmann::json::parse(read_text(out / "cues" / "summary.json"));
  EXPECT_EQ(s["actuators"].size(), 2u);
  EXPECT_GE(s["outcomes"]["sent"].get<std::size_t>(), on_changes);
  EXPECT_LE(s["outcomes"]["sent"].get<std::size_t>(), changes + 1);
}

TEST_F(RumbleCli, KnownAnswersOnAHandWrittenScanFile) {
  // Three scans, 61 bins -30 .. 30 deg: (1) one obstacle straight ahead at 1 m, (2) a wall 0.8 m
  // ahead in every bin, (3) nothing.
  std::string text = "t_ns,ground,ransac,obstacle_points,drop_off_points";
  for (int b = -30; b <= 30; ++b) text += ",r_" + std::to_string(b);
  text += "\n1000000000,0,1,10,0";
  for (int b = -30; b <= 30; ++b) text += b == 0 ? ",1.000" : ",";
  text += "\n1500000000,0,1,900,0";
  for (int b = -30; b <= 30; ++b) text += "," + std::to_string(0.8 / std::cos(b * M_PI / 180.0));
  text += "\n2500000000,0,1,0,0";
  for (int b = -30; b <= 30; ++b) text += ",";
  text += "\n";
  write_text(path("hand.csv"), text);
  const fs::path out = path("rumble-hand");
  const auto r = navaid_cli("rumble --scans '" + path("hand.csv").string() + "' --function ficf --out '" +
                            out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = read_csv(out / "rumble.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_NEAR(std::stod(rows[1][1]), 0.331155, 1e-5);  // exp(4.5 - 1) / 100, eq. 2.12
  EXPECT_EQ(rows[1][4], "off");                         // below 3.0
  EXPECT_GT(std::stod(rows[2][1]), 3.0);
  EXPECT_EQ(rows[2][4], "both");  // symmetric wall: no freer side
  EXPECT_EQ(rows[3][1], "0");
  EXPECT_EQ(rows[3][4], "off");
  const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(s["state_changes"].get<int>(), 2);
  EXPECT_EQ(s["states"]["off"]["scans"].get<int>(), 2);
  EXPECT_EQ(s["states"]["both"]["scans"].get<int>(), 1);
  EXPECT_NEAR(s["states"]["off"]["seconds"].get<double>(), 0.5, 1e-9);  // the last scan holds for 0 s
  EXPECT_NEAR(s["states"]["both"]["seconds"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(s["duration_s"].get<double>(), 1.5, 1e-9);
  EXPECT_NE(r.output.find("state changes (rumble signals): 2"), std::string::npos) << r.output;
  // A raised forward threshold silences the wall.
  const auto raised = navaid_cli("rumble --scans '" + path("hand.csv").string() + "' --function ficf --out '" +
                                 out.string() + "' --set planning.byu.ficf.forward_threshold=1000");
  ASSERT_EQ(raised.status, 0) << raised.output;
  EXPECT_EQ(read_csv(out / "rumble.csv")[2][4], "off");
}

TEST_F(RumbleCli, Errors) {
  const std::string out = " --out '" + path("rumble-errors").string() + "'";
  const std::string scans = " --scans '" + (input("map") / "obstacle_scan.csv").string() + "'";
  const auto bad_function = navaid_cli("rumble" + scans + " --function vfh" + out);
  EXPECT_EQ(bad_function.status, 2);
  EXPECT_NE(bad_function.output.find("--function must be ficf or cacf, not 'vfh'"), std::string::npos)
      << bad_function.output;
  const auto unknown_key = navaid_cli("rumble" + scans + " --function ficf --set planning.byu.ficf.widht_m=1" + out);
  EXPECT_EQ(unknown_key.status, 2);
  EXPECT_NE(unknown_key.output.find("planning.byu.ficf.widht_m"), std::string::npos) << unknown_key.output;
  const auto bad_range = navaid_cli("rumble" + scans + " --function cacf --set planning.byu.cacf.width_m=0" + out);
  EXPECT_EQ(bad_range.status, 2);
  EXPECT_NE(bad_range.output.find("planning.byu.cacf.width_m"), std::string::npos) << bad_range.output;
  // A corrupt copy of the real file: a non-numeric drop-off range on its third line.
  std::istringstream in(read_text(input("map") / "obstacle_scan.csv"));
  std::string header, row1, row2;
  std::getline(in, header);
  std::getline(in, row1);
  std::getline(in, row2);
  row2 = row2.substr(0, row2.rfind(',')) + ",x";
  write_text(path("corrupt.csv"), header + "\n" + row1 + "\n" + row2 + "\n");
  const auto corrupt = navaid_cli("rumble --scans '" + path("corrupt.csv").string() + "' --function ficf" + out);
  EXPECT_EQ(corrupt.status, 2);
  EXPECT_NE(corrupt.output.find(path("corrupt.csv").string() + ":3:"), std::string::npos) << corrupt.output;
  EXPECT_NE(corrupt.output.find("d_30"), std::string::npos) << corrupt.output;  // the last column: the drop-off at 30 deg
  const auto missing = navaid_cli("rumble --scans /nonexistent/obstacle_scan.csv --function ficf" + out);
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("/nonexistent/obstacle_scan.csv"), std::string::npos) << missing.output;
}

}  // namespace
