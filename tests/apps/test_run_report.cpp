// The self-contained HTML report of a full-device run (experiments/figures/run_report.py): what
// it embeds, what it says about inputs a run did not write, and that headless Chromium opens it
// with every figure loaded and no script error, and sees a broken figure, broken speech or a
// script error when there is one.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "browser_check.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

int run_report(const fs::path& run, const fs::path& log) {
  const std::string command = "/usr/bin/python3 '" + std::string(NAVAID_SOURCE_DIR) +
                              "/experiments/figures/run_report.py' '" + run.string() + "' > '" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A 2x2 greyscale PNG (a checkerboard), for the run's own figure files.
const char kTinyPng[] =
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x02\x00\x00\x00\x02\x08\x00"
    "\x00\x00\x00\x57\xdd\x52\xf8\x00\x00\x00\x0c\x49\x44\x41\x54\x78\xda\x63\x60\xf8\x0f\x84\x00\x06\x00\x01"
    "\xff\xad\x2c\x37\x25\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82";

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

/// 0.2 s of 16-bit mono silence at 16 kHz: a 44-byte RIFF header and the samples.
std::string silent_wav() {
  const std::uint32_t samples = 3200, data = samples * 2;
  std::string wav = "RIFF";
  const auto u32 = [&](std::uint32_t v) { for (int i = 0; i < 4; ++i) wav += static_cast<char>((v >> (8 * i)) & 0xff); };
  const auto u16 = [&](std::uint16_t v) { for (int i = 0; i < 2; ++i) wav += static_cast<char>((v >> (8 * i)) & 0xff); };
  u32(36 + data);
  wav += "WAVEfmt ";
  u32(16);     // fmt chunk size
  u16(1);      // PCM
  u16(1);      // mono
  u32(16000);  // sample rate
  u32(32000);  // byte rate
  u16(2);      // block align
  u16(16);     // bits per sample
  wav += "data";
  u32(data);
  return wav + std::string(data, '\0');
}

/// A small run folder as navaid run --device writes it: a circle walked (the full estimates header
/// with empty ENU fields), three plans (one not found), cues with a quoted spoken text that holds
/// a comma, stage timing, latency, a top view and 0.2 s of silence as speech.
void write_run(const fs::path& run) {
  fs::create_directories(run);
  write_text(run / "summary.json",
             R"({"recording": "sim/walk", "frames": 50, "device": {"name": "smart-cane", "actuator": "wheel"},)"
             R"( "pipeline": {"mode": "replay", "wall_s": 4.0, "recording_s": 5.0, "realtime_factor": 1.25},)"
             R"( "ate": {"rmse_m": 0.05, "path_length_m": 6.2},)"
             R"( "stages": {"mapping": {"median_ms": 20.0, "p99_ms": 40.0}, "planning": {"median_ms": 0.5}},)"
             R"( "latency": {"median_ms": 30.0, "p99_ms": 48.0, "cues": 10}, "guidance": {"plans": 3}})");
  std::string est = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode,"
                    "cov_pxx,cov_pxy,cov_pxz,cov_pyy,cov_pyz,cov_pzz,cov_rxx,cov_rxy,cov_rxz,cov_ryy,cov_ryz,cov_rzz,"
                    "enu_yaw,enu_x,enu_y,enu_z\n";
  std::string stages = "t_ns,frontend_ms,estimator_ms,mapping_ms,planning_ms,interaction_ms\n";
  std::string latency = "frame_t_ns,cue_t_s,kind,latency_ms\n";
  for (int i = 0; i < 50; ++i) {
    const double a = 0.1256 * i;
    const long long t = 1000000000LL + 100000000LL * i;
    est += std::to_string(t) + "," + std::to_string(std::cos(a)) + "," + std::to_string(std::sin(a)) +
           ",0,1,0,0,0,0,0,0,0,0,0,0,0,0," + (i < 5 ? "initializing" : i == 30 ? "imu-only" : "rgbd-vio") +
           ",0.01,0,0,0.01,0,0.01,0.001,0,0,0.001,0,0.001,,,,\n";
    // Mapping runs every third frame; the others leave it empty.
    stages += std::to_string(t) + ",12.5,30.1," + (i % 3 == 0 ? "20.0" : "") + ",0.5,0.02\n";
    if (i % 5 == 0) latency += std::to_string(t) + "," + std::to_string(0.1 * i) + ",turn," + std::to_string(40 + i) + "\n";
  }
  write_text(run / "estimates.csv", est);
  write_text(run / "stages.csv", stages);
  write_text(run / "latency.csv", latency);
  write_text(run / "plans.csv",
             "t_ns,planner,status,reason,length_m,expanded,time_ms,path\n"
             "1500000000,wpg,found,path-found,1.5,40,1.2,1.000:0.000 1.500:0.500 1.000:1.000\n"
             "2500000000,wpg,not-found,no-path,0.000,900,3.4,\n"
             "3500000000,wpg,found,path-found,2.0,60,1.1,0.000:1.000 -1.000:0.000\n");
  write_text(run / "cues.csv",
             "t_s,channel,outcome,kind,priority,direction_deg,steering_deg,rumble,hand,message,text,duration_s,pattern\n"
             "1.000000000,haptic,sent,turn,50,20,12.5,,,prepare_turn,,,0:390:0:0:125\n"
             "1.100000000,speech,spoken,obstacle,80,,,,,obstacle_ahead,\"Obstacle ahead, go left.\",1.2,\n"
             "1.200000000,haptic,refreshed,turn,50,20,12.5,,,prepare_turn,,,0:390:0:0:125\n"
             "1.300000000,speech,rate-limited,veer,40,,,,,veer_left,Veer left.,,\n"
             "1.500000000,speech,duplicate,obstacle,80,,,,,obstacle_ahead,\"Obstacle ahead, go left.\",,\n"
             "2.300000000,speech,finished,obstacle,80,,,,,obstacle_ahead,\"Obstacle ahead, go left.\",,\n"
             "2.500000000,speech,spoken,arrive,90,,,,,arrived,Arrived.,0.8,\n"
             "3.000000000,haptic,switched-off,turn,50,,0,,,,,,\n"
             "3.300000000,speech,finished,arrive,90,,,,,arrived,Arrived.,,\n"
             "3.400000000,system,expired,system,10,,,,,locating,Locating.,,\n");
  write_bytes(run / "topview.png", std::string(kTinyPng, sizeof kTinyPng - 1));
  write_bytes(run / "speech.wav", silent_wav());
}

TEST(RunReport, EmbedsEverythingInOnePage) {
  ScratchDir dir("run-report");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  const std::string page = read_text(dir / "report.html");
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);  // self-contained
  EXPECT_EQ(page.find("href=\"http"), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  EXPECT_EQ(page.find("<script src"), std::string::npos);
  EXPECT_NE(page.find("data:audio/wav;base64,"), std::string::npos);
  EXPECT_NE(page.find("Obstacle ahead, go left."), std::string::npos);  // quoted CSV field with a comma
  EXPECT_NE(page.find("Arrived."), std::string::npos);
  EXPECT_NE(page.find("smart-cane"), std::string::npos);
  EXPECT_NE(page.find("<tr><th>not found</th><td>1</td></tr>"), std::string::npos);
  EXPECT_NE(page.find("Top view of the estimated track"), std::string::npos);
}

TEST(RunReport, MissingInputsAreNotedNotFatal) {
  ScratchDir dir("run-report-summary-only");
  write_text(dir / "summary.json", R"({"recording": "sim/walk", "device": {"name": "w-roma", "speech": "off"}})");
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  const std::string page = read_text(dir / "report.html");
  EXPECT_NE(page.find("no speech: run with device.speech off"), std::string::npos);
  EXPECT_NE(page.find("no estimates.csv"), std::string::npos);
  EXPECT_NE(page.find("no stages.csv"), std::string::npos);
  EXPECT_EQ(page.find("<img"), std::string::npos);
}

TEST(RunReport, OpensInHeadlessChromiumWithEveryFigureLoaded) {
  ScratchDir dir("run-report-chromium");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  const auto check = navaid::testing::check_page_in_chromium(dir / "report.html");
  if (!navaid::testing::browser_available(check)) return;
  EXPECT_EQ(check.status, "ok") << check.dom.substr(0, 400);
  EXPECT_EQ(check.errors, "0");
  EXPECT_EQ(check.figures, "6/6");  // trajectory, top view, cue timeline, timing, latency and the audio
}

TEST(RunReport, ChromiumSeesABrokenFigure) {
  ScratchDir dir("run-report-broken");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  std::string page = read_text(dir / "report.html");
  const auto at = page.find("<h2>Map</h2>");
  ASSERT_NE(at, std::string::npos);
  page.insert(at, "<img src=\"data:image/png;base64,AAAA\" alt=\"broken\">");
  write_text(dir / "broken.html", page);
  const auto check = navaid::testing::check_page_in_chromium(dir / "broken.html");
  if (!navaid::testing::browser_available(check)) return;
  EXPECT_EQ(check.status, "failed");
  EXPECT_EQ(check.figures, "6/7");
  EXPECT_EQ(check.errors, "0");  // a figure that does not decode is not a script error
}

TEST(RunReport, ChromiumSeesBrokenSpeech) {
  ScratchDir dir("run-report-audio");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  std::string page = read_text(dir / "report.html");
  const std::string uri = "data:audio/wav;base64,";
  const auto at = page.find(uri);
  ASSERT_NE(at, std::string::npos);
  page.replace(at, page.find('"', at) - at, uri + "AAAA");  // no longer a WAV
  write_text(dir / "audio.html", page);
  const auto check = navaid::testing::check_page_in_chromium(dir / "audio.html");
  if (!navaid::testing::browser_available(check)) return;
  EXPECT_EQ(check.status, "failed");
  EXPECT_EQ(check.figures, "5/6");
}

TEST(RunReport, ChromiumSeesAScriptError) {
  ScratchDir dir("run-report-script");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  std::string page = read_text(dir / "report.html");
  page.insert(page.find("<h2>Map</h2>"), "<script>undefined_function();</script>");
  write_text(dir / "script.html", page);
  const auto check = navaid::testing::check_page_in_chromium(dir / "script.html");
  if (!navaid::testing::browser_available(check)) return;
  EXPECT_EQ(check.status, "failed");
  EXPECT_EQ(check.errors, "1");
}

TEST(RunReport, AMissingOrBrokenSummaryIsNamed) {
  ScratchDir dir("run-report-empty");
  EXPECT_NE(run_report(dir.path(), dir / "log.txt"), 0);
  EXPECT_NE(read_text(dir / "log.txt").find("summary.json"), std::string::npos);
  write_text(dir / "summary.json", "{\"frames\": ");  // cut short
  EXPECT_NE(run_report(dir.path(), dir / "log.txt"), 0);
  EXPECT_NE(read_text(dir / "log.txt").find("summary.json: not readable JSON"), std::string::npos);
}

}  // namespace
