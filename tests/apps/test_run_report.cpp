// The self-contained HTML report of a full-device run (experiments/figures/run_report.py): what
// it embeds, and that headless Chromium opens it with every figure loaded and no script error,
// and sees a broken figure when there is one.
#include <gtest/gtest.h>

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

/// A small run folder as navaid run --device writes it: a circle walked, three plans (one not
/// found), cues with a quoted spoken text, stage timing, latency and 0.2 s of silence as speech.
void write_run(const fs::path& run) {
  fs::create_directories(run);
  write_text(run / "summary.json",
             R"({"recording": "sim/walk", "frames": 50, "device": {"name": "smart-cane", "actuator": "wheel"},)"
             R"( "pipeline": {"mode": "replay", "wall_s": 4.0, "recording_s": 5.0, "realtime_factor": 1.25},)"
             R"( "stages": {"mapping": {"median_ms": 20.0, "p99_ms": 40.0}}, "latency": {"median_ms": 30.0}})");
  std::string est = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode\n";
  std::string stages = "t_ns,frontend_ms,estimator_ms,mapping_ms,planning_ms,interaction_ms\n";
  std::string latency = "frame_t_ns,cue_t_s,kind,latency_ms\n";
  for (int i = 0; i < 50; ++i) {
    const double a = 0.1256 * i;
    const long long t = 1000000000LL + 100000000LL * i;
    est += std::to_string(t) + "," + std::to_string(std::cos(a)) + "," + std::to_string(std::sin(a)) +
           ",0,1,0,0,0,0,0,0,0,0,0,0,0,0," + (i < 5 ? "initializing" : "rgbd-vio") + "\n";
    stages += std::to_string(t) + ",12.5,30.1," + (i % 3 == 0 ? "20.0" : "0.1") + ",0.5,0.02\n";
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
             "1.0,haptic,sent,turn,50,20,,,,,,,s:0.3\n"
             "1.1,speech,spoken,obstacle,80,,,,,obstacle,\"Obstacle ahead, go left.\",1.2,\n"
             "2.3,speech,finished,obstacle,80,,,,,obstacle,\"Obstacle ahead, go left.\",,\n"
             "3.0,haptic,refreshed,turn,50,20,,,,,,,s:0.3\n");
  // 0.2 s of 16-bit mono silence at 16 kHz.
  const std::uint32_t samples = 3200, data = samples * 2;
  std::string wav = "RIFF";
  const auto u32 = [&](std::uint32_t v) { for (int i = 0; i < 4; ++i) wav += static_cast<char>((v >> (8 * i)) & 0xff); };
  const auto u16 = [&](std::uint16_t v) { for (int i = 0; i < 2; ++i) wav += static_cast<char>((v >> (8 * i)) & 0xff); };
  u32(36 + data);
  wav += "WAVEfmt ";
  u32(16);
  u16(1);
  u16(1);
  u32(16000);
  u32(32000);
  u16(2);
  u16(16);
  wav += "data";
  u32(data);
  wav += std::string(data, '\0');
  std::ofstream(run / "speech.wav", std::ios::binary) << wav;
}

TEST(RunReport, EmbedsEverythingInOnePage) {
  ScratchDir dir("run-report");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  const std::string page = read_text(dir / "report.html");
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);  // self-contained
  EXPECT_EQ(page.find("href=\"http"), std::string::npos);
  EXPECT_NE(page.find("data:audio/wav;base64,"), std::string::npos);
  EXPECT_NE(page.find("Obstacle ahead, go left."), std::string::npos);
  EXPECT_NE(page.find("smart-cane"), std::string::npos);
}

TEST(RunReport, OpensInHeadlessChromiumWithEveryFigureLoaded) {
  ScratchDir dir("run-report-chromium");
  write_run(dir.path());
  ASSERT_EQ(run_report(dir.path(), dir / "log.txt"), 0) << read_text(dir / "log.txt");
  const auto check = navaid::testing::check_page_in_chromium(dir / "report.html");
  if (!navaid::testing::browser_available(check)) return;
  EXPECT_EQ(check.status, "ok") << check.dom.substr(0, 400);
  EXPECT_EQ(check.errors, "0");
  EXPECT_EQ(check.figures, "5/5");  // trajectory, cue timeline, timing, latency and the audio (no PNG files here)
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
  EXPECT_EQ(check.figures, "5/6");
  EXPECT_EQ(check.errors, "0");  // a figure that does not decode is not a script error
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

TEST(RunReport, AFolderWithoutSummaryIsNamed) {
  ScratchDir dir("run-report-empty");
  EXPECT_NE(run_report(dir.path(), dir / "log.txt"), 0);
  EXPECT_NE(read_text(dir / "log.txt").find("summary.json"), std::string::npos);
}

}  // namespace
