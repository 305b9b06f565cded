// End-to-end tests of `navaid cues`: a hand-written guidance timeline through every device, with
// speech synthesized, as text only and off; stop pre-empting speech; replay determinism; errors.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "navaid/interaction/wav_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

// Start, a veer, a turn with a route instruction, a stop in the middle of "prepare to turn",
// locating, a voice command, arrival.
const char* const kTimeline =
    "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n"
    "0.0,event,,,,,,,,initialized,\n"
    "0.5,guidance,go,path-found,0.9,2,0.01,,,,\n"
    "1.0,guidance,go,path-found,0.9,15,0.05,,,,\n"
    "1.5,guidance,go,path-found,0.9,45,0.2,,,,\n"
    "2.0,event,,,,,,,,route_instruction,49;left;Main Street\n"
    "2.5,guidance,go,path-found,0.9,40,0.2,,,,\n"
    "3.0,guidance,stop,obstacle-ahead,1,,,,,,\n"
    "3.5,guidance,wait,locating,0.1,,,,,,\n"
    "4.0,guidance,go,path-found,0.1,30,,,,,\n"
    "6.0,guidance,go,path-found,0.9,-20,-0.1,,,,\n"
    "8.0,event,,,,,,,,voice_command,repeat\n"
    "9.0,guidance,arrived,path-found,1,,,,,,\n";

// W-ROMA hand guidance towards an object: directions every 0.5 s, then the target is reached.
const char* const kHandTimeline =
    "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n"
    "0.0,guidance,go,target-in-view,1,,,,up-right,,\n"
    "0.5,guidance,go,target-in-view,1,,,,up-right,,\n"
    "1.0,guidance,go,target-in-view,1,,,,right,,\n"
    "1.5,guidance,go,target-remembered,0.8,,,,forward,,\n"
    "2.0,guidance,go,target-remembered,0.8,,,,forward,,\n"
    "2.5,guidance,go,target-in-view,1,,,,hold,,\n"
    "3.0,guidance,arrived,target-reached,1,,,,,,\n";

struct CueRow {
  double t_s;
  std::string channel, outcome, kind, message, text, pattern;
};

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (const char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      f.emplace_back();
    } else {
      f.back() += c;
    }
  }
  return f;
}

std::vector<CueRow> read_cues(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,channel,outcome,kind,priority,direction_deg,steering_deg,rumble,hand,message,text,duration_s,pattern");
  std::vector<CueRow> rows;
  while (std::getline(in, line)) {
    const auto f = split_csv_line(line);
    EXPECT_EQ(f.size(), 13u) << line;
    if (f.size() != 13u) continue;
    rows.push_back({std::stod(f[0]), f[1], f[2], f[3], f[9], f[10], f[12]});
  }
  return rows;
}

class CuesCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("cues_cli");
    write_text(timeline(), kTimeline);
    write_text(path("hand.csv"), kHandTimeline);
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return dir_->path() / name; }
  static fs::path timeline() { return path("timeline.csv"); }
  static navaid::testing::CliRun cues(const std::string& args) {
    return navaid_cli("cues --guidance '" + timeline().string() + "' " + args);
  }
  static inline std::unique_ptr<ScratchDir> dir_;
};

TEST_F(CuesCli, BeltWithSpeechStopPreemptsAndEverythingIsWritten) {
  const fs::path out = path("belt");
  const auto r = cues("--device belt --out '" + out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("said: Stop!"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("said: Locating, please wait."), std::string::npos) << r.output;
  for (const char* f : {"cues.csv", "cues.png", "speech.wav", "summary.json", "config.yaml"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const auto rows = read_cues(out / "cues.csv");
  // The stop at 3.0 s interrupts "Prepare to turn left." and is spoken and felt at once.
  bool interrupted = false, stop_spoken = false, stop_felt = false;
  for (const CueRow& row : rows) {
    if (row.t_s == 3.0 && row.outcome == "interrupted") interrupted = row.message == "prepare_turn";
    if (row.t_s == 3.0 && row.outcome == "spoken" && row.text == "Stop!") stop_spoken = true;
    if (row.t_s == 3.0 && row.outcome == "sent" && row.kind == "stop") stop_felt = true;
  }
  EXPECT_TRUE(interrupted);
  EXPECT_TRUE(stop_spoken);
  EXPECT_TRUE(stop_felt);
  // Speech starts are at least 2.3 s apart unless a message interrupts (the Augmented Cane's gap).
  double last_start = -10.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].outcome != "spoken") continue;
    const bool interrupts = i > 0 && rows[i - 1].outcome == "interrupted";
    if (!interrupts && rows[i].kind != "stop") {
      EXPECT_GE(rows[i].t_s - last_start, 2.3 - 1e-9) << rows[i].text;
    }
    last_start = rows[i].t_s;
  }
  const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(s["device"], "belt");
  EXPECT_EQ(s["actuators"].size(), 5u);
  EXPECT_EQ(s["timeline_entries"].get<int>(), 12);
  EXPECT_EQ(s["events"].get<std::size_t>(), rows.size());
  EXPECT_GE(s["outcomes"]["interrupted"].get<int>(), 1);
  const auto wav = navaid::interaction::read_wav(out / "speech.wav");
  EXPECT_EQ(wav.sample_rate_hz, 22050);
  EXPECT_NEAR(wav.duration_s(), s["speech_wav_s"].get<double>(), 1e-3);
  EXPECT_GT(wav.duration_s(), 9.0);  // "You have arrived." starts after 9 s
}

TEST_F(CuesCli, EveryDeviceGetsItsOwnPatterns) {
  for (const auto& [device, actuators] : std::vector<std::pair<std::string, std::size_t>>{
           {"belt", 5}, {"hand", 6}, {"rumble", 2}, {"wheel", 1}}) {
    const fs::path out = path("dev-" + device);
    const std::string input = device == "hand" ? path("hand.csv").string() : timeline().string();
    const auto r = navaid_cli("cues --guidance '" + input + "' --device " + device + " --speech text --no-figure --out '" +
                              out.string() + "'");
    ASSERT_EQ(r.status, 0) << device << ": " << r.output;
    const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["actuators"].size(), actuators) << device;
    EXPECT_GT(s["outcomes"]["sent"].get<int>(), 0) << device;
    EXPECT_FALSE(fs::exists(out / "speech.wav")) << device << ": text mode writes no audio";
    EXPECT_FALSE(fs::exists(out / "cues.png")) << device;
    std::size_t patterns = 0;
    for (const CueRow& row : read_cues(out / "cues.csv")) {
      if (row.channel == "haptic" && row.outcome == "sent") {
        ++patterns;
        EXPECT_FALSE(row.pattern.empty()) << device << " at " << row.t_s;
      }
    }
    EXPECT_GT(patterns, 0u) << device;
  }
}

TEST_F(CuesCli, TextModeSchedulesLikeAudioAndOffSpeaksNothing) {
  const auto r = cues("--device belt --speech text --no-figure --out '" + path("text").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = nlohmann::json::parse(read_text(path("text") / "summary.json"));
  EXPECT_GE(s["spoken"].size(), 5u);
  EXPECT_EQ(s["spoken"][0], "Navigation ready.");
  const auto off = cues("--device belt --speech off --no-figure --out '" + path("off").string() + "'");
  ASSERT_EQ(off.status, 0) << off.output;
  const auto so = nlohmann::json::parse(read_text(path("off") / "summary.json"));
  EXPECT_EQ(so["spoken"].size(), 0u);
  EXPECT_GT(so["outcomes"]["sent"].get<int>(), 0);
}

// eLabrador's preference: audio only speaks the directions and sends no pattern; haptic only keeps
// "Stop!" and the system messages.
TEST_F(CuesCli, ModalityAudioOrHaptic) {
  const auto audio = cues("--device belt --speech text --no-figure --set interaction.cues.modality=audio --out '" +
                          path("audio").string() + "'");
  ASSERT_EQ(audio.status, 0) << audio.output;
  const auto sa = nlohmann::json::parse(read_text(path("audio") / "summary.json"));
  EXPECT_EQ(sa["outcomes"]["sent"].get<int>(), 0);
  EXPECT_EQ(sa["outcomes"]["refreshed"].get<int>(), 0);
  EXPECT_NE(sa["spoken"].dump().find("Bear right."), std::string::npos) << sa["spoken"].dump();
  const auto haptic = cues("--device belt --speech text --no-figure --set interaction.cues.modality=haptic --out '" +
                           path("haptic").string() + "'");
  ASSERT_EQ(haptic.status, 0) << haptic.output;
  const auto sh = nlohmann::json::parse(read_text(path("haptic") / "summary.json"));
  EXPECT_GT(sh["outcomes"]["sent"].get<int>(), 0);
  const std::string said = sh["spoken"].dump();
  EXPECT_EQ(said.find("Prepare to turn"), std::string::npos) << said;
  EXPECT_NE(said.find("Stop!"), std::string::npos) << said;
  EXPECT_NE(said.find("Locating, please wait."), std::string::npos) << said;
}

TEST_F(CuesCli, GermanSpeech) {
  const auto r = cues("--device hand --speech text --no-figure --set interaction.speech.language=de --out '" +
                      path("de").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("said: Halt!"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("said: Navigation bereit."), std::string::npos) << r.output;
}

TEST_F(CuesCli, SameInputSameOutputs) {
  for (const char* run : {"a", "b"}) {
    const auto r = cues(std::string("--device wheel --no-figure --out '") + path(std::string("replay-") + run).string() + "'");
    ASSERT_EQ(r.status, 0) << r.output;
  }
  EXPECT_EQ(navaid::testing::folder_contents(path("replay-a")), navaid::testing::folder_contents(path("replay-b")));
}

// --port: the timeline played out to navaid device-sim (the controller firmware behind a pty).
// The controller stops after 2 s: the link is reported lost and the user hears it.
TEST_F(CuesCli, PortPlaysToTheControllerAndALostLinkIsSpoken) {
  const fs::path link = path("belt-link");
  const std::string log = path("sim.log").string();
  const std::string start = std::string(NAVAID_CLI_PATH) + " device-sim --device belt --link '" + link.string() +
                            "' --duration 2 --status-s 0 >'" + log + "' 2>&1 &";
  ASSERT_EQ(std::system(start.c_str()), 0);
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!fs::exists(link) && std::chrono::steady_clock::now() < limit) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(fs::exists(link)) << read_text(log);
  // 12 s of timeline at 2x: 6 s of wall time, the controller gone after 2.
  const auto r = cues("--device belt --speech text --no-figure --speed 2 --port '" + link.string() + "' --out '" +
                      path("port").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = nlohmann::json::parse(read_text(path("port") / "summary.json"));
  const auto& l = s["link"];
  EXPECT_GE(l["acked"].get<int>(), 1) << l.dump();
  EXPECT_EQ(l["naks"].get<int>(), 0) << l.dump();
  EXPECT_EQ(l["link_lost_events"].get<int>(), 1) << l.dump();
  EXPECT_EQ(l["decoder"]["crc_errors"].get<int>(), 0) << l.dump();
  EXPECT_NE(s["spoken"].dump().find("Vibration link lost."), std::string::npos) << s["spoken"].dump();
  EXPECT_NE(r.output.find("link lost 1 times"), std::string::npos) << r.output;
  const auto bad = cues("--device belt --port '" + path("no-such-tty").string() + "' --out '" + path("port-bad").string() + "'");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("no-such-tty: cannot open serial port"), std::string::npos) << bad.output;
}

TEST_F(CuesCli, Errors) {
  const auto expect_error = [](const navaid::testing::CliRun& r, const std::string& text) {
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << r.output;
  };
  const std::string out = " --out '" + path("err").string() + "'";
  expect_error(cues("--device vest" + out), "--device must be belt, hand, rumble or wheel, not 'vest'");
  expect_error(cues("--device belt --speech loud" + out), "--speech must be on, off or text, not 'loud'");
  expect_error(cues("--device belt --set interaction.speech.language=fr" + out), "interaction.speech.language");
  expect_error(cues("--device belt --set interaction.belt.colour=red" + out), "interaction.belt.colour");
  expect_error(cues("--device belt --set interaction.policy.turn_min_gap_s=-1" + out), "turn_min_gap_s");
  expect_error(navaid_cli("cues --guidance '" + path("missing.csv").string() + "' --device belt" + out), "missing.csv");
  write_text(path("bad.csv"), std::string(kTimeline) + "10.0,guidance,go,path-found,0.9,,,,,,\n");
  expect_error(navaid_cli("cues --guidance '" + path("bad.csv").string() + "' --device belt" + out), "bad.csv:14");
  write_text(path("backwards.csv"), std::string(kTimeline) + "1.0,event,,,,,,,,initialized,\n");
  expect_error(navaid_cli("cues --guidance '" + path("backwards.csv").string() + "' --device belt" + out),
               "backwards.csv:14");
}

}  // namespace
