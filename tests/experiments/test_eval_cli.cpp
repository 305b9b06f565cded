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

std::string quoted_path(const fs::path& p) { return "'" + p.string() + "'"; }

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
    const CliRun run = navaid_cli("eval --est " + quoted_path(est) + " --gt " + quoted_path(gt) + " --align " + mode);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NEAR(printed_ate(run.output), expected, 1e-3) << mode << "\n" << run.output;
  }
  ScratchDir out("eval-cli");
  const CliRun run = navaid_cli("eval --est " + quoted_path(est) + " --gt " + quoted_path(gt) + " --align sim3 --rpe-lengths 1,2 --out " +
                                quoted_path(out.path()));
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
  const std::string args = "eval --est " + quoted_path(dir / "est.tum") + " --gt " + quoted_path(dir / "rec");
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
  const std::string gt_arg = " --gt " + quoted_path(dir / "gt.tum");

  CliRun run = navaid_cli("eval --est " + quoted_path(dir / "late.tum") + gt_arg);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("no estimated pose is within 0.020000000 s"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quoted_path(dir / "garbage.tum") + gt_arg);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("garbage.tum:1"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quoted_path(dir / "gt.tum") + gt_arg + " --align-frames 50");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("only 20 poses are matched"), std::string::npos) << run.output;
  run = navaid_cli("eval --est " + quoted_path(dir / "gt.tum") + gt_arg + " --tolerance -1");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("--tolerance"), std::string::npos) << run.output;
  EXPECT_NE(navaid_cli("eval --est " + quoted_path(dir / "gt.tum") + gt_arg + " --align affine").status, 0);
  EXPECT_NE(navaid_cli("eval --est " + quoted_path(dir / "missing.tum") + gt_arg).status, 0);
  EXPECT_NE(navaid_cli("eval" + gt_arg).status, 0);
}

// evo's flags (docs/evaluation.md, "evo"): -a, bare --align, -s, -as, --n_to_align, --t_max_diff,
// --delta / --delta_unit / --all_pairs; checked on a trajectory whose answers are known by hand:
// the estimate is the ground truth stretched by 1.1 and turned 30 degrees about z.
TEST(EvalCli, EvoFlags) {
  ScratchDir dir("eval-cli-evo");
  std::vector<navaid::io::StampedPose> gt, est;
  const navaid::Quat turn(Eigen::AngleAxisd(M_PI / 6, navaid::Vec3::UnitZ()));
  for (int i = 0; i < 20; ++i) {
    const navaid::Vec3 p(0.5 * i, 0.3 * std::sin(0.7 * i), 0.1 * (i % 3));
    gt.push_back({i * 100'000'000LL, navaid::SE3(navaid::Quat::Identity(), p)});
    est.push_back({i * 100'000'000LL + 3'000'000, navaid::SE3(turn, turn * (1.1 * p))});
  }
  navaid::io::write_tum_trajectory(dir / "gt.tum", gt);
  navaid::io::write_tum_trajectory(dir / "est.tum", est);
  const auto eval = [&](const std::string& flags, const std::string& name) {
    const CliRun run = navaid_cli("eval --est " + quoted_path(dir / "est.tum") + " --gt " + quoted_path(dir / "gt.tum") + " " +
                                  flags + " --no-plot --out " + quoted_path(dir / name));
    EXPECT_EQ(run.status, 0) << flags << "\n" << run.output;
    return nlohmann::json::parse(navaid::testing::read_text(dir / name / "eval.json"));
  };
  auto j = eval("-a --t_max_diff 0.01", "a");
  EXPECT_EQ(j["alignment"]["mode"], "se3");
  EXPECT_EQ(j["association"]["rule"], "evo");
  EXPECT_EQ(j["association"]["matched"], 20);  // 3 ms apart, within 10 ms
  EXPECT_EQ(eval("--align --t_max_diff 0.01", "bare")["alignment"]["mode"], "se3");
  j = eval("-as --delta 1 --delta_unit f", "as");
  EXPECT_EQ(j["alignment"]["mode"], "sim3");
  EXPECT_NEAR(j["alignment"]["scale"].get<double>(), 1.0 / 1.1, 1e-9);
  EXPECT_NEAR(j["ate"]["position_m"]["max"].get<double>(), 0.0, 1e-6);
  EXPECT_EQ(j["rpe_evo"]["pairs"], 19);
  EXPECT_NEAR(j["rpe_evo"]["translation_m"]["max"].get<double>(), 0.0, 1e-9);
  // -s alone: the scale only; relative errors vanish, absolute ones do not (no rotation applied).
  j = eval("-s --delta 2 --delta_unit m --all_pairs", "s");
  EXPECT_EQ(j["alignment"]["mode"], "scale");
  EXPECT_NEAR(j["rpe_evo"]["translation_m"]["max"].get<double>(), 0.0, 1e-9);
  EXPECT_GT(j["ate"]["position_m"]["rmse"].get<double>(), 0.5);
  EXPECT_TRUE(j["rpe_evo"]["all_pairs"].get<bool>());
  // No alignment: each frame pair sees the 10 % stretch, 0.1 of its step (the turn cancels).
  j = eval("--align none --delta 1", "none");
  double largest = 0.0;
  for (std::size_t i = 1; i < gt.size(); ++i) largest = std::max(largest, 0.1 * (gt[i].T_W_B.t - gt[i - 1].T_W_B.t).norm());
  EXPECT_NEAR(j["rpe_evo"]["translation_m"]["max"].get<double>(), largest, 1e-9);
  EXPECT_EQ(j["association"]["rule"], "rpg");
  EXPECT_EQ(eval("-a --n_to_align 5", "n")["alignment"]["frames"], 5);

  const auto fails = [&](const std::string& flags, const std::string& says) {
    const CliRun run = navaid_cli("eval --est " + quoted_path(dir / "est.tum") + " --gt " + quoted_path(dir / "gt.tum") + " " + flags);
    EXPECT_NE(run.status, 0) << flags;
    EXPECT_NE(run.output.find(says), std::string::npos) << flags << "\n" << run.output;
  };
  fails("--align 4dof -s", "--correct_scale");
  fails("-a --align sim3", "-a is --align se3");
  fails("--all_pairs", "go with --delta");
  fails("--delta 1 --delta_unit x", "--delta_unit");
  fails("--t_max_diff -1", "--t_max_diff");
  fails("--t_max_diff 0.002", "no estimated pose is within");  // the estimate lags 3 ms
  fails("--delta 1.5 --delta_unit f", "whole number");
  fails("--delta 100 --delta_unit m", "gives no pair");
}
