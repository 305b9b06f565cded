#include "navaid/interaction/synthesized_speech.hpp"

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/message_templates.hpp"

namespace navaid::interaction {
namespace {
SpeechConfig checked(SpeechConfig config) {
  if (!is_template_language(config.language)) {
    throw ConfigError("", "interaction.speech.language",
                      fmt::format("no message templates for language '{}' (there are: en, de)", config.language));
  }
  return config;
}
}  // namespace

SynthesizedSpeech::SynthesizedSpeech(SpeechConfig config) : synthesizer_(checked(std::move(config))) {}

std::string SynthesizedSpeech::text(const SpokenMessage& message) const {
  return render_message(message, synthesizer_.config().language);
}

double SynthesizedSpeech::duration_s(const SpokenMessage& /*message*/, const std::string& text) const {
  return synthesizer_.duration_s(text);
}

}  // namespace navaid::interaction
