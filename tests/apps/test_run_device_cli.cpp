// End-to-end tests of full-device runs (`navaid run --device`): each preset on a short rendered
// walk of its scenario, the run folder (map, plans, guidance and cue timelines, speech, stage
// timing, frame-to-cue latency, report), bit-identical replays, the real-time drivers, and the
// errors: a recording that cannot serve the device, a stage failing mid-run.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "browser_check.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

/// Lines of a CSV file without the columns whose names are given (wall-clock timings).
std::string csv_without(const fs::path& file, const std::vector<std::string>& drop) {
  std::ifstream in(file);
  std::string line, out;
  std::vector<bool> keep;
  bool header = true;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    if (header) {
      for (const auto& name : fields) keep.push_back(std::find(drop.begin(), drop.end(), name) == drop.end());
      header = false;
    }
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (i >= keep.size() || keep[i]) out += fields[i] + ",";
    out += "\n";
  }
  return out;
}

std::size_t data_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n > 0 ? n - 1 : 0;
}

class RunDeviceCli : public ::testing::Test {
 protected:
  // Short rendered walks (320x240 at 10 Hz, the presets' estimator rate): the Smart Cane corridor,
  // the BYU obstacle course, a W-ROMA lab walk and eLabrador's route 1, each with its default
  // mount; rendered once per build of navaid for all the suite's test processes.
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("run_device_cli");
    std::vector<std::string> commands;
    for (const auto& [scenario, seconds] : std::vector<std::pair<std::string, int>>{
             {"corridor", 6}, {"obstacle-course", 6}, {"lab-walk-1", 6}, {"route1", 4}})
      commands.push_back("simulate --scenario " + scenario + " --seed 3 --threads 2 --out {dir}/sim-" + scenario +
                         " --set duration=" + std::to_string(seconds) +
                         " --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=10");
    recordings_ = navaid::testing::shared_cli_fixture("device-walks", commands);
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static fs::path recording(const std::string& scenario) { return recordings_ / ("sim-" + scenario); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static navaid::testing::CliRun run(const std::string& scenario, const std::string& device, const fs::path& out,
                                     const std::string& extra = {}) {
    return navaid_cli("run --recording '" + recording(scenario).string() + "' --device " + device + " --out '" +
                      out.string() + "'" + extra);
  }
  static nlohmann::json summary(const fs::path& out) { return nlohmann::json::parse(read_text(out / "summary.json")); }

  static std::unique_ptr<ScratchDir> dir_;
  static fs::path recordings_;
};

std::unique_ptr<ScratchDir> RunDeviceCli::dir_;
fs::path RunDeviceCli::recordings_;

TEST_F(RunDeviceCli, SmartCaneRunsEveryLayerAndWritesTheRunFolder) {
  const fs::path out = path("smart-cane");
  const auto result = run("corridor", "smart-cane", out);
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("device smart-cane"), std::string::npos) << result.output;
  for (const char* f : {"trajectory.tum", "estimates.csv", "timing.csv", "summary.json", "config.yaml", "map/map.ot",
                        "map/summary.json", "plans.csv", "guidance_timeline.csv", "cues.csv", "stages.csv",
                        "device_stages.csv", "latency.csv", "report.html"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  const auto s = summary(out);
  EXPECT_EQ(s["device"]["name"], "smart-cane");
  EXPECT_EQ(s["device"]["guidance"], "walking-path");
  EXPECT_EQ(s["device"]["actuator"], "wheel");
  for (const char* stage : {"frontend", "estimator", "mapping", "planning", "interaction"}) {
    ASSERT_TRUE(s["stages"].contains(stage)) << stage;
    EXPECT_GT(s["stages"][stage]["frames"].get<std::size_t>(), 0u) << stage;
  }
  // The walking-path generator planned toward the corridor's end and the wheel was steered.
  EXPECT_GT(s["plans"]["found"].get<std::size_t>(), 0u) << s["plans"].dump();
  EXPECT_GT(s["cues"]["outcomes"]["sent"].get<std::size_t>(), 0u) << s["cues"].dump();
  EXPECT_GT(s["latency"]["cues"].get<std::size_t>(), 0u);
  EXPECT_EQ(data_rows(out / "latency.csv"), s["latency"]["cues"].get<std::size_t>());
  EXPECT_GT(s["pipeline"]["realtime_factor"].get<double>(), 0.0);
  EXPECT_EQ(s["device_thread"]["dropped"].get<std::size_t>(), 0u);  // replay waits, never drops
  // The report opens in a browser with every figure (map, track, cues, timing) loaded.
  const auto page = navaid::testing::check_page_in_chromium(out / "report.html");
  if (navaid::testing::browser_available(page)) {
    EXPECT_EQ(page.status, "ok") << page.figures << " figures, " << page.errors << " script errors";
  }
  // The guidance timeline is the input of navaid cues.
  const auto cues = navaid_cli("cues --guidance '" + (out / "guidance_timeline.csv").string() +
                               "' --device wheel --speech off --no-figure --out '" + path("smart-cane-cues").string() + "'");
  ASSERT_EQ(cues.status, 0) << cues.output;
  EXPECT_EQ(read_text(path("smart-cane-cues") / "cues.csv"), read_text(out / "cues.csv"));
}

TEST_F(RunDeviceCli, ReplayIsBitIdenticalAcrossRuns) {
  const fs::path a = path("replay-a"), b = path("replay-b");
  ASSERT_EQ(run("corridor", "smart-cane", a, " --no-plot").status, 0);
  ASSERT_EQ(run("corridor", "smart-cane", b, " --no-plot").status, 0);
  for (const char* f : {"estimates.csv", "trajectory.tum", "guidance_timeline.csv", "cues.csv", "map/map.ot"})
    EXPECT_TRUE(read_text(a / f) == read_text(b / f)) << f << " differs";
  // Wall-clock columns aside, the plans and the device's decisions are the same too.
  EXPECT_EQ(csv_without(a / "plans.csv", {"time_ms"}), csv_without(b / "plans.csv", {"time_ms"}));
  EXPECT_EQ(csv_without(a / "device_stages.csv", {"mapping_ms", "planning_ms", "interaction_ms"}),
            csv_without(b / "device_stages.csv", {"mapping_ms", "planning_ms", "interaction_ms"}));
}

TEST_F(RunDeviceCli, AugmentedCaneRumblesFromTheObstacleScan) {
  const fs::path out = path("augmented-cane");
  const auto result = run("obstacle-course", "augmented-cane", out, " --no-plot --set device.cost_function=ficf");
  ASSERT_EQ(result.status, 0) << result.output;
  const auto s = summary(out);
  EXPECT_EQ(s["guidance"]["function"], "ficf");
  std::size_t scans = 0;
  for (const auto& [state, n] : s["guidance"]["rumble_states"].items()) scans += n.get<std::size_t>();
  EXPECT_EQ(scans, data_rows(out / "map" / "obstacle_scan.csv"));
  EXPECT_GT(scans, 0u);
  EXPECT_FALSE(fs::exists(out / "speech.wav"));  // the preset has no speech
}

TEST_F(RunDeviceCli, WRomaGuidesTheHandAndSpeaks) {
  const fs::path out = path("w-roma");
  const auto result = run("lab-walk-1", "w-roma", out, " --no-plot");
  ASSERT_EQ(result.status, 0) << result.output;
  const auto s = summary(out);
  EXPECT_EQ(s["guidance"]["tag_id"], 5);  // from the recording's targets.csv
  EXPECT_EQ(s["device"]["actuator"], "hand");
  EXPECT_EQ(s["mapping"]["frames"]["mapped"].get<std::size_t>(), 0u);  // map_every 0: no map
  EXPECT_TRUE(fs::is_regular_file(out / "speech.wav"));
  EXPECT_GT(s["cues"]["outcomes"]["spoken"].get<std::size_t>(), 0u) << s["cues"].dump();
}

TEST_F(RunDeviceCli, ElabradorWaitsForTheGpsRegistrationAndSaysSo) {
  // Four seconds hold too few fixes for the GPS-map registration: the route is planned on the
  // scenario's streets, but no direction is given, and the user hears why.
  const fs::path out = path("elabrador");
  // The user asks where they are, then for a place the streets do not name (navaid listen's
  // voice_event.csv format; seconds from the recording's start).
  const fs::path voice = path("elabrador-voice.csv");
  write_text(voice, "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n"
                    "2.0,event,,,,,,,,voice_command,where am i\n"
                    "3.0,event,,,,,,,,voice_command,go to nowhere in particular\n");
  const auto result = run("route1", "elabrador", out, " --no-plot --set device.speech=text --voice '" + voice.string() + "'");
  ASSERT_EQ(result.status, 0) << result.output;
  const std::string timeline = read_text(out / "guidance_timeline.csv");
  EXPECT_NE(timeline.find("voice_command,where am i"), std::string::npos);
  EXPECT_NE(timeline.find("voice_command,not understood"), std::string::npos);  // no such place: the route stays
  EXPECT_EQ(read_text(out / "guidance_timeline.csv").find("go to nowhere"), std::string::npos);
  const auto s = summary(out);
  EXPECT_TRUE(fs::is_regular_file(out / "route" / "map.osm"));
  EXPECT_GT(s["guidance"]["route_length_m"].get<double>(), 200.0);
  EXPECT_EQ(s["guidance"]["withheld"].get<std::size_t>(), s["guidance"]["updates"].get<std::size_t>());
  EXPECT_EQ(s["cues"]["outcomes"]["sent"].get<std::size_t>(), 0u);  // no belt direction while unsure
  const auto spoken = s["cues"]["spoken"].dump();
  EXPECT_NE(spoken.find("Locating"), std::string::npos) << spoken;
  EXPECT_NE(read_text(out / "device_stages.csv").find("registration-uncertain"), std::string::npos);
}

TEST_F(RunDeviceCli, RealtimeRunsTheStagesOnTheirOwnThreads) {
  const fs::path out = path("realtime");
  const auto result = run("corridor", "smart-cane", out, " --no-plot --realtime --realtime-speed 1");
  ASSERT_EQ(result.status, 0) << result.output;
  const auto s = summary(out);
  EXPECT_EQ(s["pipeline"]["mode"], "realtime");
  EXPECT_EQ(s["device_thread"]["when_full"], "drop the oldest");
  EXPECT_GT(s["latency"]["cues"].get<std::size_t>(), 0u);
  EXPECT_GT(s["latency"]["p99_ms"].get<double>(), 0.0);
  // The planners acted at each frame's arrival on the newest solved estimate carried through the
  // IMU; the map followed from the solved ones.
  EXPECT_NE(s["latency"]["pose"].get<std::string>().find("through the IMU"), std::string::npos);
  EXPECT_GT(s["latency"]["prediction_span_ms"]["frames"].get<std::size_t>(), 0u);
  EXPECT_GT(s["map_latency"]["frames"].get<std::size_t>(), 0u);
  EXPECT_GT(s["plans"]["made"].get<std::size_t>(), 0u);

  const fs::path solved = path("realtime-solved");
  ASSERT_EQ(run("corridor", "smart-cane", solved, " --no-plot --realtime --set device.realtime_prediction=false").status, 0);
  EXPECT_EQ(summary(solved)["latency"]["pose"], "the frame's solved estimate");
}

TEST_F(RunDeviceCli, ARecordingThatCannotServeTheDeviceIsNamed) {
  // The corridor has no GPS: eLabrador's route needs it.
  const auto no_gps = run("corridor", "elabrador", path("no-gps"));
  EXPECT_NE(no_gps.status, 0);
  EXPECT_NE(no_gps.output.find("cannot serve device elabrador"), std::string::npos) << no_gps.output;
  EXPECT_NE(no_gps.output.find("GPS fixes"), std::string::npos) << no_gps.output;
  const auto unknown = run("corridor", "white-cane", path("unknown"));
  EXPECT_NE(unknown.status, 0);
  EXPECT_NE(unknown.output.find("no device preset 'white-cane'"), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("augmented-cane, elabrador, smart-cane, w-roma"), std::string::npos) << unknown.output;
  const auto both = navaid_cli("run --recording '" + recording("corridor").string() +
                               "' --device smart-cane --config /dev/null --out '" + path("both").string() + "'");
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.output.find("not both"), std::string::npos) << both.output;
  const auto voice_alone = navaid_cli("run --recording '" + recording("corridor").string() + "' --voice '" +
                                      (recording("corridor") / "imu.csv").string() + "' --out '" + path("voice").string() + "'");
  EXPECT_NE(voice_alone.status, 0);
  EXPECT_NE(voice_alone.output.find("--voice needs a device"), std::string::npos) << voice_alone.output;
  write_text(path("not-voice.csv"), "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n"
                                    "1.0,event,,,,,,,,voice_command,sing a song\n");
  const auto not_voice = run("corridor", "smart-cane", path("not-voice"), " --voice '" + path("not-voice.csv").string() + "'");
  EXPECT_NE(not_voice.status, 0);
  EXPECT_NE(not_voice.output.find("not-voice.csv"), std::string::npos) << not_voice.output;
  EXPECT_NE(not_voice.output.find("'sing a song' is no voice command"), std::string::npos) << not_voice.output;
  const auto bad_key = run("corridor", "smart-cane", path("bad-key"), " --set device.actuator=bell");
  EXPECT_NE(bad_key.status, 0);
  EXPECT_NE(bad_key.output.find("device.actuator"), std::string::npos) << bad_key.output;
}

TEST_F(RunDeviceCli, RealEurocImagesWithoutDepthAreRefusedOrRunDegraded) {
  // The real EuRoC V1_01 frames have IMU but no depth: W-ROMA's preset names what is missing;
  // told to do without, hand guidance runs bearing-only (case II) on the real images.
  if (!navaid::testing::have_shared_data()) return;
  const fs::path euroc = navaid::testing::shared_data_dir() / "euroc-V1_01-micro";
  const auto refused = navaid_cli("run --recording '" + euroc.string() + "' --device w-roma --out '" +
                                  path("euroc-refused").string() + "'");
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.output.find("cannot serve device w-roma: it lacks depth images"), std::string::npos)
      << refused.output;
  const fs::path out = path("euroc-degraded");
  const auto degraded = navaid_cli("run --recording '" + euroc.string() + "' --device w-roma --no-plot --out '" +
                                   out.string() + "' --set device.needs=[] --set device.tag_id=0");
  ASSERT_EQ(degraded.status, 0) << degraded.output;
  const auto s = summary(out);
  EXPECT_EQ(s["depth"], false);  // VIO
  EXPECT_GT(s["estimates"]["with_frame"].get<std::size_t>(), 40u);
  EXPECT_EQ(data_rows(out / "device_stages.csv"), s["estimates"]["with_frame"].get<std::size_t>());
}

TEST_F(RunDeviceCli, AStageThatFailsMidRunIsNamedAndTheOutputsSoFarAreKept) {
  // A copy of the corridor walk whose 30th labels image is corrupt: only the mapping stage reads
  // labels, so the estimator goes on and the run stops there.
  const fs::path rec = path("sim-corrupt");
  fs::copy(recording("corridor"), rec, fs::copy_options::recursive);
  std::vector<fs::path> labels;
  for (const auto& e : fs::recursive_directory_iterator(rec))
    if (e.is_regular_file() && e.path().string().find("/labels/") != std::string::npos) labels.push_back(e.path());
  std::sort(labels.begin(), labels.end());
  ASSERT_GT(labels.size(), 40u);
  std::ofstream(labels[30], std::ios::trunc) << "not a PNG";
  const fs::path out = path("corrupt");
  const auto result = navaid_cli("run --recording '" + rec.string() + "' --device smart-cane --no-plot --out '" +
                                 out.string() + "' --set device.map_every=1");
  EXPECT_NE(result.status, 0);
  EXPECT_NE(result.output.find("mapping stage failed at frame 30"), std::string::npos) << result.output;
  EXPECT_NE(read_text(out / "error.txt").find("mapping stage failed at frame 30"), std::string::npos);
  EXPECT_GE(data_rows(out / "estimates.csv"), 30u);
  EXPECT_EQ(data_rows(out / "device_stages.csv"), 30u);  // frames 0..29 went through every stage
  EXPECT_TRUE(fs::is_regular_file(out / "guidance_timeline.csv"));
  EXPECT_TRUE(fs::is_regular_file(out / "cues.csv"));
}

}  // namespace
