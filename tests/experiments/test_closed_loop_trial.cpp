// Closed-loop trials: a simulated person walks by the cues of the full-device pipeline, sensors
// rendered from where they truly are. Replays bit for bit from the seed; the white cane misses the
// corridor's hanging board; each device's cues reach the person; bad set-ups are refused by name.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/closed_loop_trial.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/experiments/recording_run.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/experiments/trial_reproduction.hpp"
#include "navaid/experiments/trial_study.hpp"
#include "test_support.hpp"

namespace {

using namespace navaid;
using namespace navaid::experiments;
namespace fs = std::filesystem;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

Config no_device(const std::vector<std::string>& overrides = {}) { return Config::parse("{}", "<test>", overrides); }
Config preset(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return Config::load(runtime::device_preset_file(name), overrides);
}

TEST(ClosedLoopTrial, ACaneUserInTheCorridorReplaysBitForBitAndMissesTheHangingBoard) {
  ScratchDir dir("trial_cane");
  const TrialResult a = run_trial({"corridor", 0, 4, no_device()}, dir / "a");
  const TrialResult b = run_trial({"corridor", 0, 4, no_device()}, dir / "b");
  for (const char* f : {"track.csv", "contacts.csv", "instructions.csv", "config.yaml", "simulation.yaml"})
    EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
  EXPECT_EQ(a.success, b.success);
  EXPECT_GT(a.path_length_m, 9.0);  // at least the corridor's length
  EXPECT_GT(a.cane_contacts, 0u);   // the low box, the cabinet and the walls are felt
  // The two-point-touch cane finds only what reaches the ground: walking the corridor, people
  // meet the board hung at 1.3-1.9 m with the head, never with the cane.
  std::size_t board_head = 0, board_cane = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    for (const auto& c : run_trial({"corridor", 0, seed, no_device()}, dir / "s").contacts) {
      if (c.semantic != simulation::SemanticClass::kTrafficSign) continue;
      (c.part == simulation::BodyPart::kCane ? board_cane : board_head) += c.part == simulation::BodyPart::kHead ||
                                                                               c.part == simulation::BodyPart::kCane;
    }
  EXPECT_GT(board_head, 0u);
  EXPECT_EQ(board_cane, 0u);
  // Another seed is another person.
  const TrialResult c = run_trial({"corridor", 0, 5, no_device()}, dir / "c");
  EXPECT_NE(read_text(dir / "a" / "track.csv"), read_text(dir / "c" / "track.csv"));
}

TEST(ClosedLoopTrial, TheSmartCaneSteersThePersonThroughTheWholePipelineAndReplays) {
  ScratchDir dir("trial_smart_cane");
  const std::vector<std::string> o = {"trial.timeout_s=12"};
  const TrialResult a = run_trial({"corridor", 0, 1, preset("smart-cane", o)}, dir / "a");
  run_trial({"corridor", 0, 1, preset("smart-cane", o)}, dir / "b");
  for (const char* f : {"track.csv", "instructions.csv", "contacts.csv", "guidance_timeline.csv", "cues.csv"})
    EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
  // The wheel's pull reached the person and moved them; the estimator followed the true walk.
  EXPECT_NE(read_text(dir / "a" / "instructions.csv").find(",steer,"), std::string::npos);
  EXPECT_GT(a.path_length_m, 1.0);
  EXPECT_GT(a.user.instructions, 10u);
  const auto& time = a.summary["time"];
  EXPECT_GT(time["frames"].get<int>(), 50);
  EXPECT_TRUE(a.summary["device_run"].contains("stages"));
}

TEST(ClosedLoopTrial, TheAugmentedCaneRumblesAndThePersonTurnsAway) {
  ScratchDir dir("trial_augmented");
  const TrialResult r = run_trial({"obstacle-course", 0, 2, preset("augmented-cane")}, dir.path());
  const std::string felt = read_text(dir / "instructions.csv");
  EXPECT_TRUE(felt.find(",turn-toward,") != std::string::npos || felt.find(",halt,") != std::string::npos);
  EXPECT_GT(r.user.corrections, 0u);
  EXPECT_GT(r.path_length_m, 8.0);
}

TEST(ClosedLoopTrial, ELabradorsUserWalksOffWhileLocatedWithGpsAndTheMagnetometerStreamed) {
  ScratchDir dir("trial_elabrador");
  const std::vector<std::string> o = {"trial.timeout_s=15"};
  const TrialResult a = run_trial({"route1", 0, 1, preset("elabrador", o)}, dir / "a");
  run_trial({"route1", 0, 1, preset("elabrador", o)}, dir / "b");
  for (const char* f : {"track.csv", "instructions.csv", "guidance_timeline.csv"})
    EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
  const auto& time = a.summary["time"];
  EXPECT_GE(time["gps_fixes"].get<int>(), 14);      // 1 Hz over 16 s, none lost in the open street
  EXPECT_GE(time["mag_samples"].get<int>(), 700);   // 50 Hz
  // "Locating, please wait" while the GPS-map registration needs a walked track: the user walks
  // the first street meanwhile instead of standing for ever.
  EXPECT_NE(read_text(dir / "a" / "instructions.csv").find(",wait,"), std::string::npos);
  EXPECT_GT(a.path_length_m, 6.0);
  EXPECT_FALSE(a.success);  // 272 m of route in 15 s
}

TEST(ClosedLoopTrial, ARouteTrialEndsWhereThePersonStopsAndNeedsTheLandmarkFaced) {
  ScratchDir dir("trial_route_facing");
  // A cane user who knows the turns stops at the destination facing the way they came (east);
  // the park's board stands north of it, so they arrive without facing it (the paper's W: 0).
  const TrialResult w = run_trial({"route1", 0, 1, no_device({"trial.face_landmark=true"})}, dir / "w");
  EXPECT_EQ(w.outcome, "not-facing");
  EXPECT_FALSE(w.success);
  EXPECT_FALSE(w.faced_landmark);
  EXPECT_LE(w.goal_distance_m, 3.0);
  EXPECT_FALSE(w.summary["faced_landmark"].get<bool>());
  EXPECT_EQ(w.summary["experimenter_corrections"].get<std::size_t>(), w.experimenter_corrections);
  // With the phone's turn points off by metres the walk differs, replayably.
  const std::vector<std::string> gps = {"trial.face_landmark=true", "trial.turn_point_sigma_m=3"};
  run_trial({"route1", 0, 1, no_device(gps)}, dir / "g1");
  run_trial({"route1", 0, 1, no_device(gps)}, dir / "g2");
  EXPECT_EQ(read_text(dir / "g1" / "track.csv"), read_text(dir / "g2" / "track.csv"));
  EXPECT_NE(read_text(dir / "g1" / "track.csv"), read_text(dir / "w" / "track.csv"));
  // Only the street scenarios have a destination landmark.
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"corridor", 0, 1, no_device({"trial.face_landmark=true"})}, dir / "c"); })
                .find("no destination landmark"),
            std::string::npos);
}

TEST(ClosedLoopTrial, ItsSensorStreamsSavedAsARecordingReplayTheEstimatorToTheSameEstimate) {
  ScratchDir dir("trial_recording");
  const std::vector<std::string> o = {"trial.timeout_s=12", "trial.save_recording=true"};
  run_trial({"corridor", 0, 1, preset("smart-cane", o)}, dir / "t");
  const io::Recording rec = io::read_navaid_recording(dir / "t" / "recording");
  ASSERT_FALSE(rec.features.empty());
  EXPECT_EQ(rec.imu.size(), rec.groundtruth.size());  // the true state at every IMU sample
  EXPECT_NEAR(rec.calibration.cameras.front().rate_hz, 10.0, 1e-9);  // the preset's rate, as fed
  EXPECT_FALSE(rec.landmarks.empty());
  // `navaid run` on it with the device's estimator keys ends where the trial's estimate ended.
  RecordingRunOptions run;
  run.recording = dir / "t" / "recording";
  run.out = dir / "run";
  run.plot = false;
  run.config = Config::parse("{}", "<test>", {"estimator.solver.max_iterations=12"});
  run_recording(run);
  std::istringstream track(read_text(dir / "t" / "track.csv")), estimates(read_text(dir / "run" / "estimates.csv"));
  std::string line, last_track, last_estimate;
  while (std::getline(track, line)) last_track = line;
  while (std::getline(estimates, line)) last_estimate = line;
  auto field = [](const std::string& csv, int i) {
    std::istringstream in(csv);
    std::string f;
    for (int k = 0; k <= i; ++k) std::getline(in, f, ',');
    return std::stod(f);
  };
  // est_x and est_y are written with 4 decimals at the 0.1 s track tick
  EXPECT_NEAR(field(last_track, 6), field(last_estimate, 1), 2e-4);
  EXPECT_NEAR(field(last_track, 7), field(last_estimate, 2), 2e-4);
  // Without a device there is nothing to record.
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"corridor", 0, 1, no_device({"trial.save_recording=true"})}, dir / "n"); })
                .find("needs a device"),
            std::string::npos);
}

// W-ROMA's task (reach_protocol.hpp): the start in the central aisle, as the reproduction's.
const std::vector<std::string> kReach = {"trial.task=reach", "trial.reach.start_xy=[7.3,3.4]"};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(ClosedLoopTrial, WithoutADeviceThePersonSearchesFromMemoryAndReplays) {
  ScratchDir dir("trial_reach_memory");
  const TrialResult a = run_trial({"lab-walk-1", 0, 3, no_device(kReach)}, dir / "a");
  run_trial({"lab-walk-1", 0, 3, no_device(kReach)}, dir / "b");
  for (const char* f : {"track.csv", "contacts.csv", "targets.csv"})
    EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
  const auto& reach = a.summary["reach"];
  EXPECT_FALSE(reach["guided"].get<bool>());
  EXPECT_GT(reach["search_start_s"].get<double>(), 5.0);  // located, then led to the start
  // Each person remembers the object with their own error: some find it within the 2 minutes, some
  // do not; a success is a touch, and its time counts from the start of the search.
  std::size_t found = 0, lost = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const TrialResult r = run_trial({"lab-walk-1", 0, seed, no_device(kReach)}, dir / "s");
    (r.success ? found : lost) += 1;
    if (r.success) {
      EXPECT_EQ(r.outcome, "touched");
      EXPECT_LE(r.summary["reach"]["closest_m"].get<double>(), 0.08);
      EXPECT_LT(r.duration_s, 120.0);
    } else {
      EXPECT_EQ(r.outcome, "timeout");
      EXPECT_NEAR(r.duration_s, 120.0, 0.01);
    }
  }
  EXPECT_GT(found, 0u);
  EXPECT_GT(lost, 0u);
}

TEST(ClosedLoopTrial, WRomasHandUnitLeadsTheHandToTheObject) {
  ScratchDir dir("trial_reach_w_roma");
  // The whole search of one person: the hand unit's cues (the tag found before the escort, the
  // object remembered through the pose once out of view) bring the hand to the box.
  const TrialResult r = run_trial({"lab-walk-1", 0, 3, preset("w-roma", kReach)}, dir / "full");
  EXPECT_TRUE(r.success) << r.outcome;
  const auto& reach = r.summary["reach"];
  EXPECT_TRUE(reach["guided"].get<bool>());
  EXPECT_GT(reach["hand_cues"].get<int>(), 5);
  EXPECT_GT(reach["turns"].get<int>() + reach["walks"].get<int>(), 2);  // the body followed the hand
  EXPECT_NE(read_text(dir / "full" / "instructions.csv").find(",move-hand,"), std::string::npos);
  EXPECT_GT(r.summary["device_run"]["guidance"]["frames_detected"].get<int>(), 10);
  // Bit for bit from the seed (a short search: 5 s).
  const auto o = with(kReach, {"trial.reach.time_limit_s=5"});
  run_trial({"lab-walk-1", 0, 1, preset("w-roma", o)}, dir / "a");
  run_trial({"lab-walk-1", 0, 1, preset("w-roma", o)}, dir / "b");
  for (const char* f : {"track.csv", "instructions.csv", "guidance_timeline.csv"})
    EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
}

TEST(ClosedLoopTrial, SetUpsThatCannotRunAreRefusedByName) {
  ScratchDir dir("trial_bad");
  // The hand unit reaches, the other devices walk; a reach needs an object to reach for.
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"lab-walk-1", 0, 1, preset("w-roma", {"trial.task=walk"})}, dir / "w"); })
                .find("trial.task"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"lab-walk-1", 0, 1, preset("smart-cane", {"trial.task=reach"})}, dir / "s"); })
                .find("trial.task"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"corridor", 0, 1, no_device({"trial.task=reach"})}, dir / "c"); })
                .find("simulation.targets"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"lab-walk-1", 0, 1, no_device({"trial.task=reach", "trial.reach.start_xy=[40,3]"})}, dir / "x"); })
                .find("trial.reach.start_xy"),
            std::string::npos);
  // A planner map is not a walk.
  EXPECT_NE(navaid::testing::error_message<UsageError>([&] { run_trial({"office1", 0, 1, no_device()}, dir / "o"); })
                .find("not a walk"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"corridor", 0, 1, no_device({"trial.goal_radius=1"})}, dir / "k"); })
                .find("trial.goal_radius"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>(
                [&] { run_trial({"corridor", 0, 1, no_device({"user.model=sprinter"})}, dir / "u"); })
                .find("user.model"),
            std::string::npos);
}

TEST(TrialStudy, TwoJobsGiveTheTrialsOneJobGivesWithIntervalsAndReplayCommands) {
  ScratchDir dir("trial_study");
  TrialStudySpec s;
  s.scenario = "corridor";
  s.device = "none";
  s.first_seed = 1;
  s.last_seed = 4;
  s.layouts = "random";
  s.quiet = true;
  s.keep = "all";
  s.jobs = 1;
  const auto one = run_trial_study(s, dir / "one");
  s.jobs = 2;
  const auto two = run_trial_study(s, dir / "two");
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::string t = "trials/seed-" + std::to_string(seed) + "/track.csv";
    EXPECT_EQ(read_text(dir / "one" / t), read_text(dir / "two" / t)) << t;
  }
  EXPECT_EQ(one["success"], two["success"]);
  const auto& success = one["success"];
  EXPECT_EQ(one["trials"].get<int>(), 4);
  EXPECT_LE(success["ci95"][0].get<double>(), success["rate"].get<double>());
  EXPECT_GE(success["ci95"][1].get<double>(), success["rate"].get<double>());
  // Every trial's row names the command that replays it, random layout included.
  const std::string csv = read_text(dir / "one" / "trials.csv");
  EXPECT_NE(csv.find("--seeds 3..3 --layouts random"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "one" / "summary.md"));
  s.last_seed = 0;
  EXPECT_THROW(run_trial_study(s, dir / "bad"), UsageError);
}

TEST(TrialReproduction, AugmentedCaneTable3_3PutsThePaperBesideOursWithAVerdict) {
  ScratchDir dir("trial_repro");
  ReproductionRequest request;
  request.out = dir / "out";
  request.seeds = 2;
  request.jobs = 2;
  const fs::path matrix = fs::path(NAVAID_SOURCE_DIR) / "experiments" / "reproductions" / "augmented-cane-table3.3.yaml";
  run_augmented_cane_table3_3(matrix, request, ReproductionEnvironment{});
  const std::string table = read_text(dir / "out" / "table3.3.md");
  EXPECT_NE(table.find("simulated users, not human results"), std::string::npos);
  EXPECT_NE(table.find("133.67 ± 33.67"), std::string::npos);  // the paper's FICF completion time
  const std::string verdict = read_text(dir / "out" / "verdict.md");
  EXPECT_TRUE(verdict.find("**Agrees**") != std::string::npos || verdict.find("**Differs**") != std::string::npos);
  EXPECT_EQ(read_text(dir / "out" / "table3.3.csv").find("measure,paper_ficf_mean"), 0u);
  request.seeds = 1;
  EXPECT_THROW(run_augmented_cane_table3_3(matrix, request, ReproductionEnvironment{}), UsageError);
}

TEST(TrialReproduction, SmartCaneTable2ComparesTheThreeMethodsPairwise) {
  ScratchDir dir("trial_repro_table2");
  ReproductionRequest request;
  request.out = dir / "out";
  request.seeds = 2;
  request.jobs = 2;
  const fs::path matrix = fs::path(NAVAID_SOURCE_DIR) / "experiments" / "reproductions" / "smart-cane-table2.yaml";
  run_smart_cane_table2(matrix, request, ReproductionEnvironment{});
  const std::string table = read_text(dir / "out" / "table2.md");
  EXPECT_NE(table.find("simulated users, not human results"), std::string::npos);
  EXPECT_NE(table.find("10.28 ± 1.48"), std::string::npos);  // the paper's WPG duration
  EXPECT_NE(table.find("p A* vs WPG"), std::string::npos);
  for (const char* study : {"two-point-touch", "astar", "wpg"})
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / study / "trials.csv")) << study;
  // The A* condition is the smart-cane device with its planner swapped (the study records both).
  const std::string astar = read_text(dir / "out" / "astar" / "summary.json");
  EXPECT_NE(astar.find("smart-cane"), std::string::npos);
  EXPECT_NE(astar.find("planning.smart_cane.planner=astar"), std::string::npos);
  const std::string verdict = read_text(dir / "out" / "verdict.md");
  EXPECT_TRUE(verdict.find("**Agrees**") != std::string::npos || verdict.find("**Differs**") != std::string::npos);
  EXPECT_NE(verdict.find("of 6 comparisons"), std::string::npos);
  EXPECT_EQ(read_text(dir / "out" / "table2.csv").find("measure,paper_two-point-touch_mean"), 0u);
  // A matrix with the wrong number of conditions is refused with the key named.
  const fs::path bad = dir / "bad.yaml";
  std::ofstream(bad) << "scenario: corridor\nuser: typical\nseeds: 2\nconditions:\n  - {key: a, label: A, device: none}\n";
  EXPECT_NE(navaid::testing::error_message<ConfigError>([&] { run_smart_cane_table2(bad, request, ReproductionEnvironment{}); })
                .find("conditions"),
            std::string::npos);
}

TEST(TrialReproduction, ElabradorFiguresCheckThePapersStatementsPerRoute) {
  ScratchDir dir("trial_repro_elabrador");
  ReproductionRequest request;
  request.out = dir / "out";
  request.seeds = 2;
  request.jobs = 2;
  // The figures' runner on a fast stand-in matrix (every condition a cane user; the real matrix's
  // eLabrador trials take minutes each and are measured in docs/reproductions.md).
  const fs::path matrix = dir / "m.yaml";
  const auto stand_in = [&matrix](const std::string& route, const std::string& w_set) {
    std::ofstream(matrix) << "routes: [" << route << "]\nuser: typical\nset: [trial.face_landmark=true]\nseeds: 2\n"
                          << "conditions:\n  - {key: w, label: W, device: none" << w_set << "}\n"
                          << "  - {key: s, label: S, device: none}\n  - {key: s-w, label: S+W, device: none}\n";
  };
  stand_in("route2", ", set: [trial.turn_point_sigma_m=3]");
  run_elabrador_fig7_8(matrix, request, ReproductionEnvironment{});
  const std::string fig = read_text(dir / "out" / "route2" / "fig8.md");
  EXPECT_NE(fig.find("simulated users, not human results"), std::string::npos);
  EXPECT_NE(fig.find("corrections (experimenter)"), std::string::npos);
  EXPECT_NE(fig.find("The paper's statements, on our means"), std::string::npos);
  for (const char* study : {"w", "s", "s-w"})
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "route2" / study / "trials.csv")) << study;
  const std::string verdict = read_text(dir / "out" / "verdict.md");
  EXPECT_NE(verdict.find("Fig. 8, Route 2"), std::string::npos);
  EXPECT_NE(verdict.find("of 4 of the paper's statements hold"), std::string::npos);
  // Route 1's text gives numbers: they are in its table beside ours.
  stand_in("route1", "");
  run_elabrador_fig7_8(matrix, request, ReproductionEnvironment{});
  const std::string fig7 = read_text(dir / "out" / "route1" / "fig7.md");
  EXPECT_NE(fig7.find("| 1.00 | 0.70 | 0.50 |"), std::string::npos);
  EXPECT_NE(fig7.find("| 0.37 | 0.00 | – |"), std::string::npos);
  EXPECT_NE(read_text(dir / "out" / "verdict.md").find("of 6 of the paper's statements hold"), std::string::npos);
  std::ofstream(matrix) << "routes: [route9]\nuser: typical\nseeds: 2\nconditions: []\n";
  EXPECT_NE(navaid::testing::error_message<ConfigError>([&] { run_elabrador_fig7_8(matrix, request, ReproductionEnvironment{}); })
                .find("routes"),
            std::string::npos);
}

}  // namespace

namespace {

TEST(TrialReproduction, WRomaTable2PutsSuccessAndTimeBesideThePapers) {
  ScratchDir dir("trial_repro_w_roma");
  ReproductionRequest request;
  request.out = dir / "out";
  request.seeds = 2;
  request.jobs = 2;
  // The registered matrix with 10 s searches (the test's time, not the study's).
  const fs::path registered = fs::path(NAVAID_SOURCE_DIR) / "experiments" / "reproductions" / "w-roma-table2.yaml";
  const fs::path matrix = dir / "w-roma-table2.yaml";
  std::string text = read_text(registered);
  const std::string anchor = "  - trial.task=reach\n";
  ASSERT_NE(text.find(anchor), std::string::npos);
  text.replace(text.find(anchor), anchor.size(), anchor + "  - trial.reach.time_limit_s=10\n");
  std::ofstream(matrix) << text;
  run_w_roma_table2(matrix, request, ReproductionEnvironment{});
  const std::string table = read_text(dir / "out" / "table2.md");
  EXPECT_NE(table.find("simulated users, not human results"), std::string::npos);
  EXPECT_NE(table.find("| success (touched or grasped within 2 min) | 0.32 | 0.96 |"), std::string::npos) << table;
  EXPECT_NE(table.find("29.10"), std::string::npos);
  for (const char* study : {"without", "with"}) EXPECT_TRUE(fs::is_regular_file(dir / "out" / study / "trials.csv")) << study;
  const std::string verdict = read_text(dir / "out" / "verdict.md");
  EXPECT_NE(verdict.find("of 2 of the paper's statements hold"), std::string::npos) << verdict;
}

}  // namespace
