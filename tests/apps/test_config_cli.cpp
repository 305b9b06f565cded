// navaid config --list: every declared key with type, default, range and doc; the configuration
// reference in docs/ is its --markdown output.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

using navaid::testing::CliRun;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;

TEST(ConfigCli, ListsEveryKeyWithTypeDefaultRangeAndDoc) {
  const CliRun run = navaid_cli("config --list", false);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("mapping.cost.unknown_cost  (number, default 0.5, [0, 1])\n    "), std::string::npos)
      << run.output.substr(0, 2000);
  for (const char* key : {"estimator.window_size", "frontend.max_features", "sensor.imu.rate", "planning.wpg.lfpc_gain",
                          "interaction.belt.refresh_hz", "device.name", "trial.task", "user.speed_mps",
                          "mapping.collision.semantic_probability", "planning.map.camera_z_m"})
    EXPECT_NE(run.output.find(std::string(key) + "  ("), std::string::npos) << key;
}

TEST(ConfigCli, PrefixListsOnlyThatSection) {
  const CliRun run = navaid_cli("config --list interaction.speech", false);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("interaction.speech.language  (string, default en, one of: en, de)"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("interaction.belt."), std::string::npos) << run.output;
  const CliRun none = navaid_cli("config --list interaction.speec");
  EXPECT_NE(none.status, 0);
  EXPECT_NE(none.output.find("no configuration key is interaction.speec"), std::string::npos) << none.output;
  EXPECT_NE(navaid_cli("config").status, 0);
}

TEST(ConfigCli, TheReferenceInDocsIsTheGeneratedListing) {
  const CliRun run = navaid_cli("config --list --markdown", false);
  ASSERT_EQ(run.status, 0) << run.output;
  const std::filesystem::path doc = std::filesystem::path(NAVAID_SOURCE_DIR) / "docs" / "config-reference.md";
  ASSERT_TRUE(std::filesystem::exists(doc)) << doc;
  EXPECT_TRUE(read_text(doc) == run.output)
      << "docs/config-reference.md is not what navaid declares; regenerate it with\n"
         "  build/apps/navaid config --list --markdown > docs/config-reference.md";
}
