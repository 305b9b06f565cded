// `navaid trial`: a small cane-only study end to end, the replay command it prints replays the
// trial bit for bit, and bad options are named.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

TEST(TrialCli, AStudyWritesItsTablesAndItsReplayCommandsReplay) {
  ScratchDir dir("trial_cli");
  const auto r = navaid_cli("trial --scenario obstacle-course --device none --user cautious --seeds 1..3 --layouts random "
                            "--jobs 2 --keep all --out '" + (dir / "study").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("simulated users, not human results"), std::string::npos) << r.output;
  const auto summary = nlohmann::json::parse(read_text(dir / "study" / "summary.json"));
  EXPECT_EQ(summary["trials"].get<int>(), 3);
  EXPECT_EQ(summary["user"], "cautious");
  const std::string csv = read_text(dir / "study" / "trials.csv");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(csv, m, std::regex("\"(navaid trial [^\"]*--seeds 2\\.\\.2[^\"]*)\"")));
  std::string replay = m[1].str().substr(std::string("navaid ").size());
  replay = std::regex_replace(replay, std::regex("--out '[^']*'"), "--out '" + (dir / "replay").string() + "'");
  const auto again = navaid_cli(replay + " --quiet");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(read_text(dir / "study" / "trials" / "seed-2" / "track.csv"),
            read_text(dir / "replay" / "trials" / "seed-2" / "track.csv"));
}

TEST(TrialCli, BadOptionsAreNamed) {
  ScratchDir dir("trial_cli_bad");
  const std::string out = " --out '" + dir.path().string() + "'";
  // (arguments, what the error must name)
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--scenario corridor --seeds 3..1", "--seeds"},
      {"--scenario corridor --device white-cane --seeds 1..1", "smart-cane"},  // the presets are listed
      {"--scenario corridor --seeds 1..1 --set user.speed=fast", "user.speed"},
      {"--seeds 1..1", "--scenario"},
  };
  for (const auto& [args, named] : cases) {
    const auto r = navaid_cli("trial " + args + out);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.output.find(named), std::string::npos) << args << "\n" << r.output;
  }
}

}  // namespace
