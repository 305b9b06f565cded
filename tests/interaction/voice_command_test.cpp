// Voice commands with pocketsphinx on speech synthesized by espeak-ng: every command recognised
// in the voices it works for, other speech rejected by the word-loop likelihood ratio, silence and
// noise give nothing, bad places and a missing model are clear errors.
#include "navaid/interaction/voice_command.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/speech_synthesizer.hpp"
#include "navaid/interaction/wav_file.hpp"

namespace navaid::interaction {
namespace {

const std::vector<std::string> kPlaces{"kitchen", "main entrance", "bus stop", "library"};
const std::vector<std::string> kCommands{"go to kitchen", "go to main entrance", "go to bus stop", "go to library",
                                         "repeat", "where am i", "stop guidance"};
const std::vector<std::string> kOtherSpeech{"the weather is nice today", "what time is it", "call my sister",
                                            "turn on the light", "hello", "thank you very much"};

/// `text` in an espeak-ng voice with 0.3 s of silence either side, as a microphone would hear it.
AudioBuffer spoken(const std::string& text, const std::string& voice) {
  SpeechConfig c;
  c.voice = voice;
  return pad_with_silence(SpeechSynthesizer(c).synthesize_uncached(text), 0.3);
}

class VoiceCommands : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { recognizer_ = std::make_unique<VoiceCommandRecognizer>(kPlaces); }
  static void TearDownTestSuite() { recognizer_.reset(); }
  static VoiceCommandRecognizer& rec() { return *recognizer_; }
  static inline std::unique_ptr<VoiceCommandRecognizer> recognizer_;
};

TEST_F(VoiceCommands, TheGrammarHoldsTheCommandsAndThePlaces) {
  EXPECT_NE(rec().grammar().find("go to <place> | repeat | where am i | stop guidance"), std::string::npos);
  EXPECT_NE(rec().grammar().find("kitchen | main entrance | bus stop | library"), std::string::npos);
  EXPECT_EQ(rec().places(), kPlaces);
  EXPECT_DOUBLE_EQ(rec().config().min_score, 0.1);
}

// Every command in the two female voices; in the four others at least 24 of 28 (measured 27-28:
// en-us sometimes hears "go to main entrance" as "where am i"; docs/interaction-voice.md).
TEST_F(VoiceCommands, EveryCommandInTheFemaleVoicesNearlyAllInTheOthers) {
  for (const char* voice : {"en+f3", "en+f5"}) {
    for (const std::string& command : kCommands) {
      const VoiceCommand r = rec().recognize(spoken(command, voice));
      EXPECT_EQ(describe(r), command) << voice << ": heard '" << r.heard << "', score " << r.score;
      EXPECT_GE(r.score, rec().config().min_score) << voice << " " << command;
    }
  }
  int right = 0;
  for (const char* voice : {"en", "en-us", "en-gb-x-rp", "en+m3"}) {
    for (const std::string& command : kCommands) right += describe(rec().recognize(spoken(command, voice))) == command;
  }
  EXPECT_GE(right, 24) << "of 28";
  const VoiceCommand go = rec().recognize(spoken("go to main entrance", "en+f3"));
  EXPECT_EQ(go.kind, VoiceCommand::Kind::kGoTo);
  EXPECT_EQ(go.place, "main entrance");
  EXPECT_EQ(to_string(go.kind), "go_to");
}

TEST_F(VoiceCommands, OtherSpeechIsMostlyNotUnderstood) {
  int accepted = 0, forced = 0, total = 0;
  for (const char* voice : {"en", "en-us", "en+m3", "en-gb-x-rp", "en+f3", "en+f5"}) {
    for (const std::string& sentence : kOtherSpeech) {
      const VoiceCommand r = rec().recognize(spoken(sentence, voice));
      ++total;
      if (!r.heard.empty()) ++forced;  // the grammar alone would have taken it for a command
      if (r.kind != VoiceCommand::Kind::kNotUnderstood) {
        ++accepted;
        std::cout << "false accept: " << voice << " '" << sentence << "' as '" << r.heard << "', score " << r.score << "\n";
      }
    }
  }
  std::cout << "other speech: grammar forced " << forced << " of " << total << ", accepted after the ratio " << accepted
            << "\n";
  // Measured on 36 sentences: the grammar forces 19-23 onto a command, the ratio lets 9-10 through
  // (docs/interaction-voice.md).
  EXPECT_LT(accepted, forced);
  EXPECT_LE(accepted, 12);
}

TEST_F(VoiceCommands, SilenceAndNoiseAreNothing) {
  AudioBuffer silence;
  silence.sample_rate_hz = 16000;
  silence.samples.assign(32000, 0);
  VoiceCommand r = rec().recognize(silence);
  EXPECT_EQ(r.kind, VoiceCommand::Kind::kNotUnderstood);
  EXPECT_EQ(describe(r), "not understood");
  AudioBuffer noise = silence;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 2000.0);
  for (auto& s : noise.samples) s = static_cast<std::int16_t>(std::clamp(n(rng), -32768.0, 32767.0));
  r = rec().recognize(noise);
  EXPECT_EQ(r.kind, VoiceCommand::Kind::kNotUnderstood) << "heard '" << r.heard << "' score " << r.score;
  AudioBuffer empty;
  empty.sample_rate_hz = 16000;
  EXPECT_EQ(rec().recognize(empty).kind, VoiceCommand::Kind::kNotUnderstood);
}

TEST_F(VoiceCommands, SixteenKilohertzInputGivesTheSameCommand) {
  const AudioBuffer a = spoken("stop guidance", "en+f5");
  const VoiceCommand at_22k = rec().recognize(a);
  const VoiceCommand at_16k = rec().recognize(resample(a, 16000));
  EXPECT_EQ(describe(at_22k), "stop guidance");
  EXPECT_EQ(describe(at_16k), "stop guidance");
}

TEST(VoiceCommandErrors, BadPlacesAndAMissingModelNameWhatIsWrong) {
  const auto error_of = [](std::vector<std::string> places, VoiceRecognizerConfig config = {}) {
    try {
      VoiceCommandRecognizer r(std::move(places), config);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of({"kitchen", "  "}).find("blank"), std::string::npos);
  EXPECT_NE(error_of({"room 101"}).find("'room 101' has the character '1'"), std::string::npos);
  EXPECT_NE(error_of({"xqzzyv hall"}).find("the word 'xqzzyv' is not in the pronunciation dictionary"), std::string::npos);
  EXPECT_NE(error_of({"kitchen", "Kitchen"}).find("given twice"), std::string::npos);
  VoiceRecognizerConfig missing;
  missing.model_dir = "/nonexistent/pocketsphinx-model";
  EXPECT_NE(error_of({"kitchen"}, missing).find("/nonexistent/pocketsphinx-model"), std::string::npos);
  VoiceRecognizerConfig bad;
  bad.min_score = std::nan("");
  EXPECT_NE(error_of({"kitchen"}, bad).find("min_score"), std::string::npos);
  // No places: a grammar without "go to".
  const VoiceCommandRecognizer none({});
  EXPECT_EQ(none.grammar().find("go to"), std::string::npos);
}

TEST(VoiceCommandErrors, RecordingWithoutAnAudioServerIsAClearError) {
  try {
    record_from_device("no-such-source", 0.5);
    GTEST_SKIP() << "an audio source answered";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-source"), std::string::npos) << e.what();
  }
  EXPECT_THROW(record_from_device("", -1.0), Error);
}

TEST(VoiceCommandWords, EveryCommandRoundTripsThroughItsWords) {
  for (const auto kind : {VoiceCommand::Kind::kGoTo, VoiceCommand::Kind::kRepeat, VoiceCommand::Kind::kWhereAmI,
                          VoiceCommand::Kind::kStopGuidance, VoiceCommand::Kind::kNotUnderstood}) {
    VoiceCommand c;
    c.kind = kind;
    if (kind == VoiceCommand::Kind::kGoTo) c.place = "main entrance";
    const auto back = voice_command_from_words(describe(c));
    ASSERT_TRUE(back.has_value()) << describe(c);
    EXPECT_EQ(back->kind, kind);
    EXPECT_EQ(back->place, c.place);
    EXPECT_EQ(back->heard, describe(c));
  }
  for (const char* other : {"", "go to ", "go to", "Repeat", "repeat ", "where am I", "take me home"})
    EXPECT_FALSE(voice_command_from_words(other).has_value()) << "'" << other << "'";
}

}  // namespace
}  // namespace navaid::interaction
