#include "navaid/interaction/speech_synthesizer.hpp"

#include <espeak-ng/speak_lib.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <set>

#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"

namespace navaid::interaction {

namespace {

constexpr const char* kVoiceKey = "interaction.speech.voice";

/// The process's one espeak-ng engine. Everything that touches espeak-ng holds mutex.
struct Engine {
  std::mutex mutex;
  bool tried = false;
  int sample_rate_hz = 0;  ///< espeak_Initialize's answer; <= 0 when it failed
  std::string current_voice;  ///< the voice last selected, so an unchanged voice is not reloaded
};

Engine& engine() {
  static Engine e;
  return e;
}

struct Collector {
  std::vector<std::int16_t>* samples;
};

int collect_samples(short* wav, int count, espeak_EVENT* events) {
  if (wav == nullptr || count <= 0 || events == nullptr) return 0;
  auto* collector = static_cast<Collector*>(events->user_data);
  if (collector != nullptr) collector->samples->insert(collector->samples->end(), wav, wav + count);
  return 0;  // 0: go on
}

/// Starts espeak-ng on first use; the caller holds the engine mutex.
void ensure_initialised(Engine& e) {
  if (!e.tried) {
    e.tried = true;
    // nullptr: espeak-ng's built-in data path (Debian: /usr/lib/x86_64-linux-gnu/espeak-ng-data),
    // or $ESPEAK_DATA_PATH when set.
    e.sample_rate_hz = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr, 0);
    if (e.sample_rate_hz > 0) espeak_SetSynthCallback(collect_samples);
  }
  if (e.sample_rate_hz <= 0) {
    throw ConfigError("<espeak-ng>", kVoiceKey,
                      "espeak-ng could not start (espeak_Initialize returned " + std::to_string(e.sample_rate_hz) +
                          "): is the espeak-ng-data package installed (/usr/lib/x86_64-linux-gnu/espeak-ng-data)?");
  }
}

/// Selects the voice; the caller holds the engine mutex and has initialised the engine.
void select_voice(Engine& e, const std::string& voice) {
  if (e.current_voice == voice) return;
  const espeak_ERROR result = espeak_SetVoiceByName(voice.c_str());
  if (result != EE_OK) {
    e.current_voice.clear();
    throw ConfigError("<espeak-ng>", kVoiceKey,
                      "espeak-ng has no voice '" + voice + "' (espeak_SetVoiceByName returned " +
                          std::to_string(static_cast<int>(result)) +
                          "); available_voices() lists them, e.g. en, en-us, en+f3, de");
  }
  e.current_voice = voice;
}

bool is_blank(std::string_view text) {
  return std::all_of(text.begin(), text.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
}

void check_ranges(const SpeechConfig& config) {
  if (config.rate_wpm < 80 || config.rate_wpm > 450) {
    throw ConfigError("<SpeechConfig>", "interaction.speech.rate_wpm",
                      "rate " + std::to_string(config.rate_wpm) + " wpm is outside [80, 450]");
  }
  if (config.pitch < 0 || config.pitch > 99) {
    throw ConfigError("<SpeechConfig>", "interaction.speech.pitch",
                      "pitch " + std::to_string(config.pitch) + " is outside [0, 99]");
  }
}

}  // namespace

std::string default_voice(std::string_view language) { return std::string(language); }

namespace {
const ConfigKey<std::string> kLanguage{"interaction.speech.language", std::string("en"), {"en", "de"},
                                       "language of the spoken messages"};
const ConfigKey<std::string> kVoice{kVoiceKey, std::nullopt, {},
                                    "espeak-ng voice (en, en-us, en+f3, de, ...); default (or empty): the language's"};
const ConfigKey<int> kRate{"interaction.speech.rate_wpm", 175, 80, 450, "speaking rate [words per minute]"};
const ConfigKey<int> kPitch{"interaction.speech.pitch", 50, 0, 99, "base pitch of the voice"};
const ConfigKey<std::string> kMode{"interaction.speech.mode", std::string("audio"), {"audio", "text"},
                                   "audio synthesises speech; text only estimates its durations"};
}  // namespace

ConfigSchema speech_config_schema() {
  return ConfigSchema().add(kLanguage).add(kVoice).add(kRate).add(kPitch).add(kMode);
}

SpeechConfig read_speech_config(const Config& config) {
  SpeechConfig out;
  out.language = get(config, kLanguage);
  out.voice = get(config, defaulting_to(kVoice, default_voice(out.language)));
  if (out.voice.empty()) out.voice = default_voice(out.language);
  out.rate_wpm = get(config, kRate);
  out.pitch = get(config, kPitch);
  out.text_only = get(config, kMode) == "text";
  return out;
}

double estimate_speech_duration_s(std::string_view text, int rate_wpm) {
  if (rate_wpm <= 0) throw UsageError("estimate_speech_duration_s: rate_wpm must be positive");
  // Units of a fifth of a word (the typist's five-character word): a letter is one, a digit four
  // (a digit is read as a word: "49" -> "forty nine"), a pause mark with text after it four.
  int units = 0;
  bool pending_break = false;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isspace(u) != 0) continue;
    if (std::strchr(".!?,;:", c) != nullptr) {
      pending_break = units > 0;
      continue;
    }
    if (pending_break) units += 4;
    pending_break = false;
    units += std::isdigit(u) != 0 ? 4 : 1;
  }
  if (units == 0) return 0.0;
  return 12.0 * (units + 1) / rate_wpm;  // 60 s/min / 5 units/word; +1: the utterance's end
}

struct SpeechSynthesizer::Cache {
  std::mutex mutex;
  std::map<std::string, AudioBuffer, std::less<>> audio;
  std::deque<std::string> order;  ///< oldest first
};

SpeechSynthesizer::SpeechSynthesizer(SpeechConfig config)
    : config_(std::move(config)), cache_(std::make_shared<Cache>()) {
  if (config_.voice.empty()) config_.voice = default_voice(config_.language);
  check_ranges(config_);
  if (config_.text_only) return;
  Engine& e = engine();
  const std::lock_guard<std::mutex> lock(e.mutex);
  ensure_initialised(e);
  select_voice(e, config_.voice);
}

AudioBuffer SpeechSynthesizer::synthesize(std::string_view text) const {
  if (config_.text_only || is_blank(text)) return synthesize_uncached(text);
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    const auto found = cache_->audio.find(text);
    if (found != cache_->audio.end()) return found->second;
  }
  AudioBuffer audio = synthesize_uncached(text);
  const std::lock_guard<std::mutex> lock(cache_->mutex);
  // Another thread may have spoken the same text meanwhile: the first one stays.
  const auto [it, inserted] = cache_->audio.emplace(std::string(text), audio);
  if (!inserted) return it->second;
  cache_->order.emplace_back(text);
  while (cache_->order.size() > kSpeechCacheEntries) {
    cache_->audio.erase(cache_->order.front());
    cache_->order.pop_front();
  }
  return audio;
}

AudioBuffer SpeechSynthesizer::synthesize_uncached(std::string_view text) const {
  AudioBuffer out;
  out.sample_rate_hz = kSpeechSampleRateHz;
  if (config_.text_only || is_blank(text)) return out;

  Engine& e = engine();
  const std::lock_guard<std::mutex> lock(e.mutex);
  ensure_initialised(e);
  out.sample_rate_hz = e.sample_rate_hz;
  select_voice(e, config_.voice);
  espeak_SetParameter(espeakRATE, config_.rate_wpm, 0);
  espeak_SetParameter(espeakPITCH, config_.pitch, 0);

  const std::string zero_terminated(text);
  Collector collector{&out.samples};
  const espeak_ERROR result = espeak_Synth(zero_terminated.c_str(), zero_terminated.size() + 1, 0, POS_CHARACTER, 0,
                                           espeakCHARS_UTF8, nullptr, &collector);
  if (result != EE_OK) {
    throw Error("espeak-ng could not synthesize \"" + zero_terminated + "\" (espeak_Synth returned " +
                std::to_string(static_cast<int>(result)) + ")");
  }
  return out;
}

double SpeechSynthesizer::duration_s(std::string_view text) const {
  if (config_.text_only) return estimate_speech_duration_s(text, config_.rate_wpm);
  return synthesize(text).duration_s();
}

std::vector<std::string> available_voices(std::string_view language) {
  Engine& e = engine();
  const std::lock_guard<std::mutex> lock(e.mutex);
  ensure_initialised(e);
  std::set<std::string> names;
  const espeak_VOICE** voices = espeak_ListVoices(nullptr);
  for (; voices != nullptr && *voices != nullptr; ++voices) {
    const espeak_VOICE* v = *voices;
    // languages: repeated (priority byte, zero-terminated language name), ended by a zero byte.
    const char* p = v->languages;
    bool speaks = language.empty();
    std::string first;
    while (p != nullptr && *p != 0) {
      const std::string lang(p + 1);
      if (first.empty()) first = lang;
      if (!speaks && (lang == language || (lang.size() > language.size() && lang.compare(0, language.size(), language) == 0 &&
                                           lang[language.size()] == '-'))) {
        speaks = true;
      }
      p += 1 + lang.size() + 1;
    }
    if (speaks && !first.empty()) names.insert(first);
  }
  return {names.begin(), names.end()};
}

}  // namespace navaid::interaction
