// End-to-end tests of `navaid eval`: the printed ATE agrees with rpg_trajectory_evaluation, the
// JSON / CSV / figure are written, ground truth may be a recording folder, bad input fails clearly.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::CliRun;
using navaid::testing::navaid_cli;
using navaid::testing::ScratchDir;

namespace {

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

double printed_ate(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(R"(ATE RMSE: ([0-9.]+) m)"))) return -1.0;
  return std::stod(m[1]);
}

fs::path rpg_dir() { return navaid::testing::shared_data_dir() / "rpg-euroc-V1_02"; }

}  // namespace

TEST(EvalCli, AgreesWithRpgAndWritesJsonCsvAndFigure) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path est = rpg_dir() / "vislam_ba" / "stamped_ba_estimate3.txt";
  const fs::path gt = rpg_dir() / "vislam_ba" / "stamped_groundtruth.txt";
  // Reference (SOURCE.md): matched=269 posyaw=0.0198 se3=0.0193 sim3=0.0120.
  const std::pair<const char*, double> modes[] = {{"posyaw", 0.0198}, {"se3", 0.0193}, {"sim3", 0.0120}};
  for (const auto& [mode, expected] : modes) {
    const CliRun run = navaid_cli("eval --est " + quote(est) + " --gt " + quote(gt) + " --align " + mode);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NEAR(printed_ate(run.output), expected, 1e-3) << mode << "\n" << run.output;
  }
  ScratchDir out("eval-cli");
  const CliRun run = navaid_cli("eval --est " + quote(est) + " --gt " + quote(gt) + " --align sim3 --rpe-lengths 1,2 --out " +
                                quote(out.path()));
  ASSERT_EQ(run.status, 0) << run.output;
  const auto j = nlohmann::json::parse(navaid::testing::read_text(out / "eval.json"));
  EXPECT_EQ(j["association"]["matched"], 269);
  EXPECT_EQ(j["alignment"]["mode"], "sim3");
  EXPECT_NEAR(j["ate"]["position_m"]["rmse"].get<double>(), 0.0120, 1e-3);
  EXPECT_NEAR(j["ate"]["position_m"]["rmse"].get<double>(), printed_ate(run.output), 1e-6);
  ASSERT_EQ(j["rpe"].size(), 7u);  // 1 m, 2 m, then 10..50 % of the path
  EXPECT_EQ(j["rpe"][0]["length_m"], 1.0);
  EXPECT_GT(j["rpe"][0]["pairs"].get<int>(), 100);
  const std::string csv = navaid::testing::read_text(out / "eval.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 270);  // header + one row per matched pose
  EXPECT_GT(fs::file_size(out / "eval.png"), 10000u);
}

TEST(EvalCli, GroundTruthFromARecordingFolder) {
  // Ground truth in a navaid recording; the estimate is the same motion in a frame turned about z
  // and moved: 4-DOF ATE 0, while no alignment sees the whole offset.
  ScratchDir dir("eval-recording");
  const auto gt = navaid::testing::synthetic_trajectory(80);
  navaid::io::Recording rec;
  rec.format = "navaid";
  for (const auto& p : gt) rec.groundtruth.push_back({p.t, p.T_W_B, std::nullopt, std::nullopt, std::nullopt});
  navaid::io::write_navaid_recording(rec, dir / "rec");
  const navaid::SE3 T(navaid::quat_from_rpy(0, 0, 0.8), navaid::Vec3(3, -1, 0.2));
  navaid::io::write_tum_trajectory(dir / "est.tum", navaid::testing::in_frame(gt, T));
  const std::string args = "eval --est " + quote(dir / "est.tum") + " --gt " + quote(dir / "rec");
  const CliRun run = navaid_cli(args);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_LT(printed_ate(run.output), 1e-5) << run.output;
  EXPECT_NE(run.output.find("matched poses: 80 of 80"), std::string::npos) << run.output;
  EXPECT_GT(printed_ate(navaid_cli(args + " --align none").output), 1.0);
}

TEST(EvalCli, BadInputFailsWithAClearMessage) {
  ScratchDir dir("eval-bad");
  const auto gt = navaid::testing::synthetic_trajectory(20);
  navaid::io::write_tum_trajectory(dir / "gt.tum", gt);
  auto late = gt;
  for (auto& p : late) p.t += 3'600'000'000'000;  // an hour later: nothing overlaps
  navaid::io::write_tum_trajectory(dir / "late.tum", late);
  navaid::testing::write_text(dir / "garbage.tum", "1.0 2.0 3.0\n");
  const std::string gt_arg = " --gt " + quote(dir / "gt.tum");

  CliRun run = navaid_cli("eval --est " + quote(dir / "late.tum") + gt_arg);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("no estimated pose is within 0.020000000 s"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quote(dir / "garbage.tum") + gt_arg);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("garbage.tum:1"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quote(dir / "gt.tum") + gt_arg + " --align-frames 50");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("only 20 poses are matched"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quote(dir / "gt.tum") + gt_arg + " --tolerance -1");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("--tolerance"), std::string::npos) << run.output;
  EXPECT_NE(navaid_cli("eval --est " + quote(dir / "gt.tum") + gt_arg + " --align affine").status, 0);
  EXPECT_NE(navaid_cli("eval --est " + quote(dir / "missing.tum") + gt_arg).status, 0);
  EXPECT_NE(navaid_cli("eval" + gt_arg).status, 0);
}
