// espeak-ng synthesis: non-silent audio at 22050 Hz whose length grows with the text and falls
// with the rate; duration_s equals samples / rate; text-only mode; unknown voices; two threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/interaction/speech_synthesizer.hpp"

namespace {

using namespace navaid;
using namespace navaid::interaction;

SpeechConfig voice(std::string name, int rate = 175) {
  SpeechConfig c;
  c.voice = std::move(name);
  c.rate_wpm = rate;
  return c;
}

double rms(const AudioBuffer& audio) {
  if (audio.samples.empty()) return 0.0;
  double sum = 0.0;
  for (const auto s : audio.samples) sum += static_cast<double>(s) * s;
  return std::sqrt(sum / static_cast<double>(audio.samples.size()));
}

TEST(SpeechSynthesizer, SpeaksNonSilentAudioAt22050Hz) {
  const SpeechSynthesizer synth(voice("en"));
  const AudioBuffer audio = synth.synthesize("system initialization completes");
  EXPECT_EQ(audio.sample_rate_hz, 22050);
  EXPECT_EQ(audio.sample_rate_hz, kSpeechSampleRateHz);
  EXPECT_GT(audio.duration_s(), 1.0);
  EXPECT_LT(audio.duration_s(), 5.0);
  EXPECT_GT(rms(audio), 300.0);
  const auto peak = *std::max_element(audio.samples.begin(), audio.samples.end(),
                                      [](std::int16_t a, std::int16_t b) { return std::abs(a) < std::abs(b); });
  EXPECT_GT(std::abs(peak), 3000);
}

TEST(SpeechSynthesizer, LongerTextLastsLonger) {
  const SpeechSynthesizer synth(voice("en"));
  const double short_s = synth.duration_s("Stop!");
  const double long_s = synth.duration_s("walk 49 meters on current road and turn left");
  EXPECT_GT(short_s, 0.2);
  EXPECT_GT(long_s, 2.0 * short_s);
}

TEST(SpeechSynthesizer, DoubleRateIsClearlyShorter) {
  const std::string text = "walk 49 meters on current road and turn left";
  const double slow = SpeechSynthesizer(voice("en", 150)).duration_s(text);
  const double fast = SpeechSynthesizer(voice("en", 300)).duration_s(text);
  EXPECT_LT(fast, 0.75 * slow) << slow << " s at 150 wpm, " << fast << " s at 300 wpm";
  EXPECT_GT(fast, 0.3 * slow);
}

TEST(SpeechSynthesizer, DurationIsSamplesOverRate) {
  const SpeechSynthesizer synth(voice("en-us"));
  const std::string text = "prepare to turn left";
  const AudioBuffer audio = synth.synthesize(text);
  EXPECT_DOUBLE_EQ(synth.duration_s(text), static_cast<double>(audio.samples.size()) / 22050.0);
}

TEST(SpeechSynthesizer, SameTextSameSamples) {
  const SpeechSynthesizer synth(voice("en"));
  EXPECT_EQ(synth.synthesize("move up right").samples, synth.synthesize("move up right").samples);
  // A copy shares the cache.
  const SpeechSynthesizer copy = synth;  // NOLINT(performance-unnecessary-copy-initialization)
  EXPECT_EQ(copy.synthesize("move up right").samples, synth.synthesize("move up right").samples);
  // espeak-ng itself: the same length within a pitch period or two.
  const double fresh = synth.synthesize_uncached("move up right").duration_s();
  EXPECT_NEAR(fresh, synth.duration_s("move up right"), 0.03);
}

TEST(SpeechSynthesizer, CacheKeepsTheLatestTexts) {
  const SpeechSynthesizer synth(voice("en", 450));
  const AudioBuffer first = synth.synthesize("one");
  for (std::size_t i = 0; i < kSpeechCacheEntries + 4; ++i) {
    EXPECT_FALSE(synth.synthesize("word " + std::to_string(i)).samples.empty());
  }
  // "one" was dropped; speaking it again still works.
  EXPECT_NEAR(synth.synthesize("one").duration_s(), first.duration_s(), 0.03);
}

TEST(SpeechSynthesizer, BlankTextIsEmpty) {
  const SpeechSynthesizer synth(voice("en"));
  EXPECT_TRUE(synth.synthesize("").samples.empty());
  EXPECT_TRUE(synth.synthesize("  \n").samples.empty());
  EXPECT_EQ(synth.synthesize("").sample_rate_hz, 22050);
}

TEST(SpeechSynthesizer, VoicesAndPitchDiffer) {
  SpeechConfig high = voice("en");
  high.pitch = 90;
  SpeechConfig low = voice("en");
  low.pitch = 10;
  const std::string text = "obstacle ahead";
  EXPECT_NE(SpeechSynthesizer(high).synthesize(text).samples, SpeechSynthesizer(low).synthesize(text).samples);
  EXPECT_NE(SpeechSynthesizer(voice("en+f3")).synthesize(text).samples,
            SpeechSynthesizer(voice("en")).synthesize(text).samples);
  const AudioBuffer german = SpeechSynthesizer(voice("de")).synthesize("Hindernis voraus");
  EXPECT_GT(rms(german), 300.0);
}

TEST(SpeechSynthesizer, TextOnlyModeEstimates) {
  SpeechConfig c = voice("en", 120);
  c.text_only = true;
  const SpeechSynthesizer synth(c);
  const AudioBuffer audio = synth.synthesize("walk 49 meters on current road and turn left");
  EXPECT_TRUE(audio.samples.empty());
  EXPECT_EQ(audio.sample_rate_hz, 22050);
  // 34 letters + 2 digits (8 units) + the end: 43 units of a fifth of a word at 120 wpm.
  EXPECT_DOUBLE_EQ(synth.duration_s("walk 49 meters on current road and turn left"), 12.0 * 43 / 120);
  // 4 letters + the end; final punctuation is no pause.
  EXPECT_DOUBLE_EQ(synth.duration_s("Stop!"), 12.0 * 5 / 120);
  // 19 letters + a comma (4) + the end.
  EXPECT_DOUBLE_EQ(synth.duration_s("obstacle ahead, go left"), 12.0 * 24 / 120);
  EXPECT_DOUBLE_EQ(estimate_speech_duration_s("obstacle ahead, go left", 240), 12.0 * 24 / 240);
  EXPECT_DOUBLE_EQ(synth.duration_s("   "), 0.0);
  EXPECT_GT(synth.duration_s("x"), 0.0);
}

TEST(SpeechSynthesizer, TextOnlyNeedsNoKnownVoice) {
  SpeechConfig c = voice("no-such-voice");
  c.text_only = true;
  EXPECT_NO_THROW(SpeechSynthesizer{c});
}

TEST(SpeechSynthesizer, TextOnlyEstimateIsNearTheRealLength) {
  SpeechConfig text_only = voice("en");
  text_only.text_only = true;
  const SpeechSynthesizer estimate(text_only);
  const SpeechSynthesizer real(voice("en"));
  for (const char* text : {"walk 49 meters on current road and turn left", "system initialization completes",
                           "network lost, mapping without semantics", "Stop!"}) {
    const double r = real.duration_s(text);
    const double e = estimate.duration_s(text);
    EXPECT_NEAR(e, r, 0.3 * r) << text;
  }
}

TEST(SpeechSynthesizer, UnknownVoiceIsAConfigError) {
  try {
    const SpeechSynthesizer synth(voice("xx-no-such-voice"));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "interaction.speech.voice");
    EXPECT_NE(std::string(e.what()).find("xx-no-such-voice"), std::string::npos) << e.what();
  }
  // The engine still works after the failed selection.
  EXPECT_GT(SpeechSynthesizer(voice("en")).synthesize("Stop!").samples.size(), 1000u);
}

TEST(SpeechSynthesizer, RangesAreChecked) {
  EXPECT_THROW(SpeechSynthesizer(voice("en", 79)), ConfigError);
  EXPECT_THROW(SpeechSynthesizer(voice("en", 451)), ConfigError);
  SpeechConfig c = voice("en");
  c.pitch = 100;
  EXPECT_THROW(SpeechSynthesizer{c}, ConfigError);
}

TEST(SpeechSynthesizer, TwoThreadsAreSafe) {
  // Two voices from two threads: espeak-ng's one voice is switched under its mutex for each call.
  const SpeechSynthesizer a(voice("en", 175));
  const SpeechSynthesizer b(voice("de", 250));
  const std::string a_text = "prepare to turn left";
  const std::string b_text = "Achtung, Hindernis voraus, bitte links gehen";
  const double a_ref = a.synthesize_uncached(a_text).duration_s();
  const double b_ref = b.synthesize_uncached(b_text).duration_s();
  ASSERT_GT(std::abs(a_ref - b_ref), 0.5);
  auto run = [](const SpeechSynthesizer& s, const std::string& text, double ref, int* good) {
    for (int i = 0; i < 10; ++i) {
      const AudioBuffer audio = i % 2 == 0 ? s.synthesize_uncached(text) : s.synthesize(text);
      if (std::abs(audio.duration_s() - ref) < 0.05 && rms(audio) > 300.0) ++*good;
    }
  };
  int a_good = 0;
  int b_good = 0;
  std::thread ta(run, std::cref(a), std::cref(a_text), a_ref, &a_good);
  std::thread tb(run, std::cref(b), std::cref(b_text), b_ref, &b_good);
  ta.join();
  tb.join();
  EXPECT_EQ(a_good, 10);
  EXPECT_EQ(b_good, 10);
}

TEST(SpeechSynthesizer, AvailableVoicesListsEnglishAndGerman) {
  const auto all = available_voices();
  EXPECT_GT(all.size(), 50u);
  const auto english = available_voices("en");
  EXPECT_NE(std::find(english.begin(), english.end(), "en-us"), english.end());
  for (const auto& v : english) EXPECT_EQ(v.rfind("en", 0), 0u) << v;
  const auto german = available_voices("de");
  EXPECT_NE(std::find(german.begin(), german.end(), "de"), german.end());
  // Every listed voice can be selected.
  for (const auto& v : german) EXPECT_NO_THROW(SpeechSynthesizer(voice(v))) << v;
}

TEST(SpeechConfigTest, ReadsKeysAndDefaults) {
  const SpeechConfig d = read_speech_config(Config{});
  EXPECT_EQ(d.language, "en");
  EXPECT_EQ(d.voice, "en");
  EXPECT_EQ(d.rate_wpm, 175);
  EXPECT_EQ(d.pitch, 50);
  EXPECT_FALSE(d.text_only);

  const Config c = Config::parse(
      "interaction:\n  speech:\n    language: de\n    rate_wpm: 220\n    pitch: 30\n    mode: text\n");
  const SpeechConfig s = read_speech_config(c);
  EXPECT_EQ(s.language, "de");
  EXPECT_EQ(s.voice, "de");
  EXPECT_EQ(s.rate_wpm, 220);
  EXPECT_EQ(s.pitch, 30);
  EXPECT_TRUE(s.text_only);
  EXPECT_NO_THROW(c.reject_unknown_keys(speech_config_schema()));

  EXPECT_EQ(read_speech_config(Config::parse("interaction: {speech: {voice: en+f3}}")).voice, "en+f3");
  EXPECT_THROW(read_speech_config(Config::parse("interaction: {speech: {rate_wpm: 500}}")), ConfigError);
  EXPECT_THROW(read_speech_config(Config::parse("interaction: {speech: {pitch: -1}}")), ConfigError);
  EXPECT_THROW(read_speech_config(Config::parse("interaction: {speech: {mode: loud}}")), ConfigError);
  EXPECT_THROW(read_speech_config(Config::parse("interaction: {speech: {language: xx}}")), ConfigError);
}

}  // namespace
