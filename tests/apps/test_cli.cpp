// End-to-end tests of the navaid program on the real data sets and on bad input.
#include <gtest/gtest.h>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::CliRun;
using navaid::testing::folder_contents;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::shared_data_dir;

namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST(Cli, HelpListsEveryCommand) {
  const CliRun run = navaid_cli("--help");
  EXPECT_EQ(run.status, 0);
  for (const char* cmd : {"info", "convert", "plot", "simulate"}) EXPECT_NE(run.output.find(cmd), std::string::npos) << cmd;
  for (const char* cmd : {"info", "convert", "plot", "simulate"}) EXPECT_EQ(navaid_cli(std::string(cmd) + " --help").status, 0) << cmd;
  EXPECT_NE(navaid_cli("").status, 0);
  EXPECT_NE(navaid_cli("frobnicate").status, 0);
}

TEST(Cli, VersionNamesTheReleaseAndTheBuild) {
  const CliRun run = navaid_cli("--version");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.output.find("navaid 0."), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Eigen 3."), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Ceres 2."), std::string::npos) << run.output;
}

TEST(Cli, InfoOnEveryCaptureOfTheGnssCollection) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path folder = shared_data_dir() / "gpsd-nmea";
  const CliRun run = navaid_cli("info --json " + quote(folder.string()), false);
  ASSERT_EQ(run.status, 0) << run.output.substr(0, 2000);
  const auto all = nlohmann::json::parse(run.output);
  std::size_t logs = 0;
  for (const auto& e : fs::directory_iterator(folder)) logs += e.path().extension() == ".log";
  ASSERT_EQ(all.size(), logs);  // every capture, and no .chk reference file
  // A capture has a GNSS track exactly when GPSD's own decoding reports a timed position for it
  // (fixes need a time; four captures never get one).
  for (const auto& s : all) {
    EXPECT_EQ(s["format"], "nmea") << s["path"];
    const std::string chk = read_text(s["path"].get<std::string>() + ".chk");
    bool gpsd_has_timed_position = false;
    std::size_t start = 0;
    while (!gpsd_has_timed_position && start < chk.size()) {
      const std::size_t end = std::min(chk.find('\n', start), chk.size());
      const std::string line = chk.substr(start, end - start);
      gpsd_has_timed_position = line.find("\"class\":\"TPV\"") != std::string::npos &&
                                line.find("\"time\"") != std::string::npos && line.find("\"lat\"") != std::string::npos;
      start = end + 1;
    }
    EXPECT_EQ(s.contains("gps_track"), gpsd_has_timed_position) << s["path"];
  }
}

TEST(Cli, InfoOnTrajectoryFolderAndFile) {
  NAVAID_REQUIRE_SHARED_DATA();
  for (const char* sub : {"vislam_ba", "vislam_rp"}) {
    const CliRun rows = navaid_cli("info --json " + quote((shared_data_dir() / "rpg-euroc-V1_02" / sub).string()), false);
    ASSERT_EQ(rows.status, 0) << sub;
    const auto members = nlohmann::json::parse(rows.output);
    EXPECT_EQ(members.size(), 11u) << sub;  // ground truth + ten estimates, not eval_cfg.yaml
    for (const auto& m : members) EXPECT_EQ(m["format"], "tum-trajectory");
  }
  const fs::path folder = shared_data_dir() / "rpg-euroc-V1_02" / "vislam_ba";
  const CliRun table = navaid_cli("info " + quote(folder.string()));
  ASSERT_EQ(table.status, 0) << table.output;
  EXPECT_NE(table.output.find("stamped_groundtruth.txt"), std::string::npos);
  EXPECT_NE(table.output.find("stamped_ba_estimate9.txt"), std::string::npos);
  EXPECT_EQ(table.output.find("eval_cfg.yaml"), std::string::npos);

  const CliRun run = navaid_cli("info --json " + quote((folder / "stamped_groundtruth.txt").string()), false);
  ASSERT_EQ(run.status, 0);
  const auto s = nlohmann::json::parse(run.output);
  EXPECT_EQ(s["format"], "tum-trajectory");
  ASSERT_TRUE(s.contains("groundtruth"));
  // The EuRoC V1_02 ground truth: 200 Hz, first stamp as in the file.
  EXPECT_EQ(s["streams"][0]["first_s"], "1403715524.907143116");
  EXPECT_NEAR(s["streams"][0]["rate_hz"].get<double>(), 200.0, 0.5);
  EXPECT_GT(s["groundtruth"]["length_m"].get<double>(), 10.0);
}

TEST(Cli, ConvertCaptureRoundTripsByteForByte) {
  NAVAID_REQUIRE_SHARED_DATA();
  ScratchDir dir("cli-convert");
  const fs::path capture = shared_data_dir() / "gpsd-nmea" / "haicom-305N.log";
  const CliRun first = navaid_cli("convert " + quote(capture.string()) + " " + quote((dir / "a").string()));
  ASSERT_EQ(first.status, 0) << first.output;
  const std::string gps_csv = read_text(dir / "a" / "gps.csv");
  const std::string header = gps_csv.substr(0, gps_csv.find('\n'));
  EXPECT_NE(header.find("lat"), std::string::npos) << header;
  EXPECT_NE(header.find("lon"), std::string::npos) << header;

  ASSERT_EQ(navaid_cli("convert " + quote((dir / "a").string()) + " " + quote((dir / "b").string())).status, 0);
  ASSERT_EQ(navaid_cli("convert " + quote((dir / "b").string()) + " " + quote((dir / "c").string())).status, 0);
  EXPECT_EQ(folder_contents(dir / "b"), folder_contents(dir / "c"));
  EXPECT_EQ(folder_contents(dir / "a"), folder_contents(dir / "b"));

  // info on the converted recording agrees with info on the capture.
  const auto from_capture = nlohmann::json::parse(navaid_cli("info --json " + quote(capture.string()), false).output);
  const auto from_recording = nlohmann::json::parse(navaid_cli("info --json " + quote((dir / "c").string()), false).output);
  EXPECT_EQ(from_capture["gps_track"], from_recording["gps_track"]);
}

TEST(Cli, ConvertRefusesToOverwriteAndCollections) {
  NAVAID_REQUIRE_SHARED_DATA();
  ScratchDir dir("cli-refuse");
  const fs::path capture = shared_data_dir() / "gpsd-nmea" / "haicom-305N.log";
  ASSERT_EQ(navaid_cli("convert " + quote(capture.string()) + " " + quote((dir / "a").string())).status, 0);
  const CliRun again = navaid_cli("convert " + quote(capture.string()) + " " + quote((dir / "a").string()));
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.output.find("--overwrite"), std::string::npos) << again.output;
  EXPECT_EQ(navaid_cli("convert --overwrite " + quote(capture.string()) + " " + quote((dir / "a").string())).status, 0);
  const CliRun collection = navaid_cli("convert " + quote((shared_data_dir() / "gpsd-nmea").string()) + " " +
                                    quote((dir / "x").string()));
  EXPECT_EQ(collection.status, 2);
  EXPECT_NE(collection.output.find("one file at a time"), std::string::npos) << collection.output;
}

// A version 2 recording holding only feature observations and landmarks, written by hand as an
// external front end would: 5 frames at 10 Hz, frame 2 without features; frame k != 2 sees tracks
// k, k+1, k+2, with depth on even ids. Known answers: 12 observations, 2.4 per frame, 6 of 12 with
// depth, 7 tracks (0..6), track 6 without a landmark.
TEST(Cli, InfoOnFeatureRecording) {
  ScratchDir dir("cli-features");
  const fs::path rec = dir / "features-only";
  fs::create_directories(rec);
  navaid::testing::write_text(rec / "recording.yaml",
                              "format: navaid-recording\nversion: 2\nsensors: [features, landmarks]\n");
  navaid::testing::write_text(rec / "calibration.yaml", "cameras: []\n");
  std::string features = "t_ns,camera,track_id,u,v,depth\n";
  for (int k = 0; k < 5; ++k) {
    const std::string t = std::to_string(1'000'000'000 + k * 100'000'000);
    if (k == 2) features += t + ",cam0,,,,\n";
    for (int id = k; k != 2 && id < k + 3; ++id)
      features += t + ",cam0," + std::to_string(id) + ",12.5,-0.25," + (id % 2 == 0 ? "3.5" : "") + "\n";
  }
  navaid::testing::write_text(rec / "features.csv", features);
  std::string landmarks = "track_id,x,y,z\n";
  for (int id = 0; id < 6; ++id) landmarks += std::to_string(id) + ",1,-2,0.5\n";
  navaid::testing::write_text(rec / "landmarks.csv", landmarks);

  const CliRun run = navaid_cli("info --json " + quote(rec.string()), false);
  ASSERT_EQ(run.status, 0) << run.output;
  const auto s = nlohmann::json::parse(run.output);
  ASSERT_EQ(s["streams"].size(), 1u);
  EXPECT_EQ(s["streams"][0]["name"], "cam0 features");
  EXPECT_EQ(s["streams"][0]["count"], 5);
  EXPECT_NEAR(s["streams"][0]["rate_hz"].get<double>(), 10.0, 1e-9);
  ASSERT_EQ(s["features"].size(), 1u);
  const auto& f = s["features"][0];
  EXPECT_EQ(f["camera"], "cam0");
  EXPECT_EQ(f["frames"], 5);
  EXPECT_EQ(f["empty_frames"], 1);
  EXPECT_EQ(f["observations"], 12);
  EXPECT_EQ(f["tracks"], 7);
  EXPECT_DOUBLE_EQ(f["mean_per_frame"].get<double>(), 2.4);
  EXPECT_DOUBLE_EQ(f["depth_fraction"].get<double>(), 0.5);
  EXPECT_EQ(s["landmarks"], 6);
  EXPECT_EQ(s["tracks_without_landmark"], 1);

  const CliRun text = navaid_cli("info " + quote(rec.string()));
  ASSERT_EQ(text.status, 0) << text.output;
  EXPECT_NE(text.output.find("cam0: 5 frames (1 without features), 2.4 per frame, 50.0% with depth, 7 tracks"),
            std::string::npos)
      << text.output;
  EXPECT_NE(text.output.find("6 (1 feature tracks without one)"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("no ground-truth landmark"), std::string::npos) << text.output;

  // The hand-written files are already in the writer's canonical form.
  ASSERT_EQ(navaid_cli("convert " + quote(rec.string()) + " " + quote((dir / "out").string())).status, 0);
  EXPECT_EQ(read_text(dir / "out" / "features.csv"), features);
  EXPECT_EQ(read_text(dir / "out" / "landmarks.csv"), landmarks);
}

TEST(Cli, BadInputGivesClearErrors) {
  ScratchDir dir("cli-bad");
  const CliRun missing = navaid_cli("info " + quote((dir / "nothing-here").string()));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("nothing-here"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("does not exist"), std::string::npos) << missing.output;

  navaid::testing::write_text(dir / "notes.txt", "hello\nworld\n");
  const CliRun unknown = navaid_cli("info " + quote((dir / "notes.txt").string()));
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("not a recognised file"), std::string::npos) << unknown.output;

  navaid::testing::write_text(dir / "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n1.5 0 0 0 0 0 0 1\n");
  const CliRun decreasing = navaid_cli("info " + quote((dir / "traj.txt").string()));
  EXPECT_EQ(decreasing.status, 2);
  EXPECT_NE(decreasing.output.find("traj.txt:3"), std::string::npos) << decreasing.output;

  EXPECT_NE(navaid_cli("info --format bogus " + quote((dir / "traj.txt").string())).status, 0);
}

TEST(Cli, PlotWritesAFigure) {
  NAVAID_REQUIRE_SHARED_DATA();
  ScratchDir dir("cli-plot");
  const fs::path capture = shared_data_dir() / "gpsd-nmea" / "haicom-305N.log";
  const CliRun run = navaid_cli("plot " + quote(capture.string()) + " --out " + quote((dir / "track.png").string()));
  ASSERT_EQ(run.status, 0) << run.output;
  ASSERT_TRUE(fs::exists(dir / "track.png"));
  EXPECT_GT(fs::file_size(dir / "track.png"), 10000u);
  const std::string png = read_text(dir / "track.png");
  EXPECT_EQ(png.substr(1, 3), "PNG");
}
