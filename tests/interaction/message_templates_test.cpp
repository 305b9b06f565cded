// Message templates (English, German) and the synthesized-speech renderer the scheduler uses.
#include "navaid/interaction/message_templates.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/cue_generator.hpp"
#include "navaid/interaction/synthesized_speech.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {
namespace {

SpokenMessage msg(std::string id, std::map<std::string, std::string> args = {}) {
  return SpokenMessage{MessageCategory::kSystem, std::move(id), std::move(args)};
}

TEST(MessageTemplates, KnownAnswersInEnglish) {
  EXPECT_EQ(render_message(msg("stop"), "en"), "Stop!");
  EXPECT_EQ(render_message(msg("locating"), "en"), "Locating, please wait.");
  EXPECT_EQ(render_message(msg("prepare_turn", {{"side", "left"}}), "en"), "Prepare to turn left.");
  EXPECT_EQ(render_message(msg("move_hand", {{"direction", "up-right"}}), "en"), "Move up and right.");
  EXPECT_EQ(render_message(msg("move_hand", {{"direction", "hold"}}), "en"), "Hold still.");
  EXPECT_EQ(render_message(msg("mode_changed", {{"mode", "vio"}}), "en"), "Tracking mode: camera only.");
  EXPECT_EQ(render_message(msg("route", {{"distance_m", "49"}, {"turn", "right"}, {"road", "Main Street"}}), "en"),
            "In 49 meters, turn right onto Main Street.");
  EXPECT_EQ(render_message(msg("destination_set", {{"place", "bus stop"}}), "en"), "Destination set: bus stop.");
}

TEST(MessageTemplates, OptionalPartsDisappearWithoutTheirArgument) {
  EXPECT_EQ(render_message(msg("route", {{"distance_m", "12.5"}, {"turn", "straight"}}), "en"),
            "In 12.5 meters, continue straight.");
  EXPECT_EQ(render_message(msg("route", {{"distance_m", "12"}, {"turn", "left"}}), "de"), "In 12 Metern links abbiegen.");
  EXPECT_EQ(render_message(msg("route", {{"distance_m", "12"}, {"turn", "left"}, {"road", "Hauptstraße"}}), "de"),
            "In 12 Metern links abbiegen, Hauptstraße.");
}

TEST(MessageTemplates, KnownAnswersInGerman) {
  EXPECT_EQ(render_message(msg("stop"), "de"), "Halt!");
  EXPECT_EQ(render_message(msg("prepare_turn", {{"side", "right"}}), "de"), "Gleich rechts abbiegen.");
  EXPECT_EQ(render_message(msg("locating"), "de"), "Ortung läuft, bitte warten.");
  EXPECT_EQ(render_message(msg("mode_changed", {{"mode", "imu-only"}}), "de"), "Ortungsmodus: nur Bewegungssensoren.");
}

TEST(MessageTemplates, EveryTemplateHasBothLanguagesAndDistinctTexts) {
  std::set<std::string> ids;
  for (const MessageTemplateInfo& info : template_ids()) {
    EXPECT_TRUE(ids.insert(std::string(info.id)).second) << info.id;
    std::map<std::string, std::string> args;
    for (const std::string& a : info.args) {
      if (a.back() == '?') continue;
      // A value every argument kind accepts.
      args[a] = a == "side" ? "left" : a == "direction" ? "up" : a == "turn" ? "left" : a == "mode" ? "vio" : a == "way" ? "stop"
              : a == "distance_m" || a == "clock" ? "10" : "north gate";
    }
    const std::string en = render_message(msg(std::string(info.id), args), "en");
    const std::string de = render_message(msg(std::string(info.id), args), "de");
    EXPECT_FALSE(en.empty()) << info.id;
    EXPECT_FALSE(de.empty()) << info.id;
    EXPECT_EQ(en.find_first_of("{}[]"), std::string::npos) << en;
    EXPECT_EQ(de.find_first_of("{}[]"), std::string::npos) << de;
    if (info.id != "move_hand") {
      EXPECT_NE(en, de) << info.id;
    }
  }
  EXPECT_GE(ids.size(), 23u);
}

// Every message the cue generator can produce has words, in both languages.
TEST(MessageTemplates, EveryGeneratedMessageRenders) {
  CueGenerator g;
  std::vector<Cue> cues;
  const auto add = [&](std::vector<Cue> more) { cues.insert(cues.end(), more.begin(), more.end()); };
  double t = 0.0;
  const auto ev = [&](SystemEventKind kind, std::string value = {}) {
    t += 1.0;
    add(g.on_event(SystemEvent{seconds_to_ns(t), kind, std::move(value)}));
  };
  ev(SystemEventKind::kInitialized);
  for (const char* mode : {"initializing", "rgbd-vio", "vio", "imu-only", "lost"}) ev(SystemEventKind::kEstimatorMode, mode);
  ev(SystemEventKind::kNetworkLost);
  ev(SystemEventKind::kNetworkRestored);
  ev(SystemEventKind::kLinkLost);
  ev(SystemEventKind::kLinkRestored);
  ev(SystemEventKind::kCameraFault, "depth stream stalled");
  ev(SystemEventKind::kVoiceCommand, "repeat");
  ev(SystemEventKind::kRouteInstruction, "49;left;Main Street");
  ev(SystemEventKind::kRouteInstruction, "120;straight");
  ev(SystemEventKind::kRouteInstruction, "15;cross;Hauptstrasse");
  ev(SystemEventKind::kRouteInstruction, "30;steps");
  ev(SystemEventKind::kVoiceCommand, "where am i");
  ev(SystemEventKind::kVoiceCommand, "go to bus stop");
  ev(SystemEventKind::kVoiceCommand, "sing a song");
  planning::GuidanceCommand c;
  for (const double heading_deg : {0.0, 60.0, -60.0}) {
    t += 1.0;
    c.t = seconds_to_ns(t);
    c.action = planning::GuidanceAction::kGo;
    c.confidence = 1.0;
    c.heading_rad = planning::deg_to_rad(heading_deg);
    add(g.on_guidance(c));
  }
  for (int d = 0; d <= static_cast<int>(planning::HandDirection::kBackward); ++d) {
    t += 1.0;
    c.t = seconds_to_ns(t);
    c.heading_rad.reset();
    c.hand = static_cast<planning::HandDirection>(d);
    add(g.on_guidance(c));
  }
  c.hand.reset();
  c.confidence = 0.0;
  t += 1.0;
  c.t = seconds_to_ns(t);
  add(g.on_guidance(c));  // locating
  c.confidence = 1.0;
  for (const auto action : {planning::GuidanceAction::kStop, planning::GuidanceAction::kArrived}) {
    t += 1.0;
    c.t = seconds_to_ns(t);
    c.action = action;
    add(g.on_guidance(c));
  }
  ev(SystemEventKind::kVoiceCommand, "stop guidance");
  // Spoken directions of the audio-only preference.
  CueGeneratorConfig audio;
  audio.modality = CueModality::kAudio;
  CueGenerator heard(audio);
  for (const double heading_deg : {20.0, -20.0}) {
    t += 1.0;
    planning::GuidanceCommand v;
    v.t = seconds_to_ns(t);
    v.action = planning::GuidanceAction::kGo;
    v.confidence = 1.0;
    v.heading_rad = planning::deg_to_rad(heading_deg);
    add(heard.on_guidance(v));
  }
  for (const auto r : {planning::RumbleState::kLeft, planning::RumbleState::kRight, planning::RumbleState::kBoth}) {
    t += 1.0;
    planning::GuidanceCommand o;
    o.t = seconds_to_ns(t);
    o.action = planning::GuidanceAction::kGo;
    o.confidence = 1.0;
    o.rumble = r;
    add(heard.on_guidance(o));
  }
  {
    // Arrived, with the destination's landmark to face.
    t += 1.0;
    planning::GuidanceCommand a;
    a.t = seconds_to_ns(t);
    a.action = planning::GuidanceAction::kArrived;
    a.confidence = 1.0;
    a.heading_rad = planning::deg_to_rad(85.0);
    add(heard.on_guidance(a));
  }
  std::set<std::string> seen;
  for (const Cue& cue : cues) {
    if (!cue.message) continue;
    seen.insert(cue.message->id);
    for (const char* lang : {"en", "de"}) {
      EXPECT_NO_THROW(render_message(*cue.message, lang)) << cue.message->id << " in " << lang;
    }
  }
  for (const char* id : {"initialized", "mode_changed", "network_lost", "network_restored", "link_lost",
                         "link_restored", "camera_fault", "route", "destination_set", "not_understood",
                         "prepare_turn", "move_hand", "locating", "stop", "arrived", "guidance_stopped", "bear", "obstacle", "route_crossing", "route_steps", "arrived_facing"}) {
    EXPECT_TRUE(seen.count(id)) << id << " was never generated";
  }
}

TEST(MessageTemplates, BadMessagesNameWhatIsWrong) {
  const auto error_of = [](const SpokenMessage& m, const char* lang = "en") {
    try {
      render_message(m, lang);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(msg("sing")).find("no message template 'sing'"), std::string::npos);
  EXPECT_NE(error_of(msg("prepare_turn")).find("needs argument 'side'"), std::string::npos);
  EXPECT_NE(error_of(msg("prepare_turn", {{"side", "up"}})).find("'up' is not one of left, right"), std::string::npos);
  EXPECT_NE(error_of(msg("stop", {{"side", "left"}})).find("takes no argument 'side'"), std::string::npos);
  EXPECT_NE(error_of(msg("route", {{"distance_m", "ten"}, {"turn", "left"}})).find("'ten' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of(msg("destination_set", {{"place", "  "}})).find("place is blank"), std::string::npos);
  EXPECT_NE(error_of(msg("stop"), "fr").find("language 'fr'"), std::string::npos);
}

TEST(SynthesizedSpeech, TextOnlyTimesMessagesByTheEstimate) {
  SpeechConfig config;
  config.text_only = true;
  const SynthesizedSpeech speech(config);
  const SpokenMessage m = msg("prepare_turn", {{"side", "left"}});
  const std::string text = speech.text(m);
  EXPECT_EQ(text, "Prepare to turn left.");
  EXPECT_DOUBLE_EQ(speech.duration_s(m, text), estimate_speech_duration_s(text, config.rate_wpm));
  EXPECT_TRUE(speech.audio(text).samples.empty());
}

TEST(SynthesizedSpeech, DurationIsTheLengthOfTheAudio) {
  const SynthesizedSpeech speech(SpeechConfig{});
  const SpokenMessage m = msg("locating");
  const std::string text = speech.text(m);
  const AudioBuffer audio = speech.audio(text);
  ASSERT_FALSE(audio.samples.empty());
  EXPECT_EQ(audio.sample_rate_hz, speech.sample_rate_hz());
  EXPECT_DOUBLE_EQ(speech.duration_s(m, text), audio.duration_s());
  EXPECT_GT(audio.duration_s(), 0.8);  // "Locating, please wait." at 175 wpm
  EXPECT_LT(audio.duration_s(), 3.0);
}

TEST(SynthesizedSpeech, GermanTemplatesWithTheGermanVoice) {
  SpeechConfig config;
  config.language = "de";
  const SynthesizedSpeech speech(config);
  EXPECT_EQ(speech.config().voice, "de");
  EXPECT_EQ(speech.text(msg("stop")), "Halt!");
  EXPECT_GT(speech.audio("Halt!").duration_s(), 0.2);
}

TEST(SynthesizedSpeech, LanguageWithoutTemplatesIsAConfigError) {
  SpeechConfig config;
  config.language = "fr";
  config.text_only = true;
  EXPECT_THROW(SynthesizedSpeech{config}, ConfigError);
}

}  // namespace
}  // namespace navaid::interaction
