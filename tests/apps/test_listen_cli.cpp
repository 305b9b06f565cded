// End-to-end tests of `navaid listen`: a command spoken by espeak-ng into a WAV, recognised, its
// voice_event.csv fed to `navaid cues`; silence not understood; bad input errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "navaid/interaction/speech_synthesizer.hpp"
#include "navaid/interaction/wav_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

void say(const std::string& text, const fs::path& wav) {
  navaid::interaction::SpeechConfig c;
  c.voice = "en+f5";
  navaid::interaction::write_wav(wav, navaid::interaction::SpeechSynthesizer(c).synthesize(text));
}

TEST(ListenCli, ASpokenDestinationReachesTheCues) {
  const ScratchDir dir("listen_cli");
  say("go to bus stop", dir / "bus.wav");
  const auto r = navaid_cli("listen --wav '" + (dir / "bus.wav").string() + "' --places 'kitchen,bus stop' --at 2.5 --out '" +
                            (dir / "heard").string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("go to bus stop", 0), 0u) << r.output;
  const auto j = nlohmann::json::parse(read_text(dir / "heard" / "result.json"));
  EXPECT_EQ(j["command"], "go_to");
  EXPECT_EQ(j["place"], "bus stop");
  EXPECT_GE(j["score"].get<double>(), j["min_score"].get<double>());
  EXPECT_EQ(read_text(dir / "heard" / "voice_event.csv"),
            "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n"
            "2.500000000,event,,,,,,,,voice_command,go to bus stop\n");
  const auto cues = navaid_cli("cues --guidance '" + (dir / "heard" / "voice_event.csv").string() +
                               "' --device belt --speech text --no-figure --out '" + (dir / "cues").string() + "'");
  ASSERT_EQ(cues.status, 0) << cues.output;
  EXPECT_NE(cues.output.find("said: Destination set: bus stop."), std::string::npos) << cues.output;
}

TEST(ListenCli, SilenceIsNotUnderstoodAndExitsThree) {
  const ScratchDir dir("listen_cli_silence");
  navaid::interaction::AudioBuffer silence;
  silence.sample_rate_hz = 16000;
  silence.samples.assign(24000, 0);
  navaid::interaction::write_wav(dir / "quiet.wav", silence);
  const auto r = navaid_cli("listen --wav '" + (dir / "quiet.wav").string() + "' --out '" + (dir / "q").string() + "'");
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_EQ(r.output.rfind("not understood", 0), 0u) << r.output;
  EXPECT_EQ(read_text(dir / "q" / "voice_event.csv"),
            "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n");
}

TEST(ListenCli, BadInput) {
  const ScratchDir dir("listen_cli_bad");
  const auto expect_error = [](const navaid::testing::CliRun& r, const std::string& text) {
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << r.output;
  };
  expect_error(navaid_cli("listen --wav '" + (dir / "missing.wav").string() + "'"), "missing.wav");
  write_text(dir / "text.wav", "this is not audio");
  expect_error(navaid_cli("listen --wav '" + (dir / "text.wav").string() + "'"), "text.wav");
  say("repeat", dir / "repeat.wav");
  expect_error(navaid_cli("listen --wav '" + (dir / "repeat.wav").string() + "' --places 'room 101'"),
               "'room 101' has the character '1'");
  expect_error(navaid_cli("listen"), "give either --wav FILE or --device NAME");
  expect_error(navaid_cli("listen --wav '" + (dir / "repeat.wav").string() + "' --device x"), "give either");
}

}  // namespace
