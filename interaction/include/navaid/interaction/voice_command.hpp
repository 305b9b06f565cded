#pragma once
// Voice commands (eLabrador: the user changes the destination or asks for information by voice):
// "go to <place>", "repeat", "where am i", "stop guidance", recognised with pocketsphinx 0.8
// against a JSGF grammar built from the place names of the route or scenario
// (thirdparty-notes/pocketsphinx.md, docs/interaction-voice.md).
//
// Out-of-grammar speech is rejected by a likelihood ratio: the same audio is decoded a second time
// with a loop of 300 common English words (and the command and place words); the command path
// must score at least `min_score` nats per second of speech above that loop. A grammar forces any
// speech onto some command, so the ratio is what tells "repeat" from "the weather is nice today".
// pocketsphinx and sphinxbase stay in the .cpp.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/interaction/audio_buffer.hpp"

namespace navaid::interaction {

struct VoiceCommand {
  enum class Kind { kGoTo, kRepeat, kWhereAmI, kStopGuidance, kNotUnderstood };
  Kind kind = Kind::kNotUnderstood;
  /// The place for kGoTo, as given to the recognizer (e.g. "main entrance"); empty otherwise.
  std::string place;
  /// The grammar's hypothesis, words separated by one space ("go to main entrance"); empty when
  /// the grammar found nothing. For a rejected utterance it is what the grammar would have chosen.
  std::string heard;
  /// Confidence: log-likelihood of the command path minus the word loop's, in nats per second of
  /// speech (higher is more confident); -infinity when nothing was heard, +infinity when the loop
  /// found nothing.
  double score = 0.0;
};

/// "go_to", "repeat", "where_am_i", "stop_guidance", "not_understood".
std::string_view to_string(VoiceCommand::Kind kind);
/// The command as a user would say it ("go to kitchen", "repeat", ...) or "not understood".
std::string describe(const VoiceCommand& command);
/// The inverse of describe: "go to <place>", "repeat", "where am i", "stop guidance", "not
/// understood" (a guidance timeline's voice_command value, navaid listen's voice_event.csv); nullopt
/// for other words. The score is not carried: +infinity (the command was accepted).
std::optional<VoiceCommand> voice_command_from_words(std::string_view said);

struct VoiceRecognizerConfig {
  /// pocketsphinx-en-us: holds en-us/ (acoustic model) and cmudict-en-us.dict. Empty: the
  /// model found at build time (/usr/share/pocketsphinx/model/en-us).
  std::filesystem::path model_dir;
  /// Rejection threshold on VoiceCommand::score [nats per second of speech]
  /// (docs/interaction-voice.md: where it sits between commands and other speech, measured).
  double min_score = 0.1;
  /// Below this many frames (10 ms each) of grammar path the utterance counts as nothing heard.
  int min_speech_frames = 20;
};

class VoiceCommandRecognizer {
 public:
  /// Builds the grammar for `places` (e.g. {"kitchen", "main entrance", "bus stop"}: lower or
  /// upper case, words of letters, apostrophes and hyphens separated by spaces) and starts
  /// pocketsphinx. Throws navaid::Error naming the place and the word when a word is not in the
  /// pronunciation dictionary or a place is blank or has other characters, and when the model
  /// cannot be loaded (naming the folder). With no places, the grammar has no "go to".
  explicit VoiceCommandRecognizer(std::vector<std::string> places, VoiceRecognizerConfig config = {});
  ~VoiceCommandRecognizer();
  VoiceCommandRecognizer(VoiceCommandRecognizer&&) noexcept;
  VoiceCommandRecognizer& operator=(VoiceCommandRecognizer&&) noexcept;

  /// Decodes one utterance (any rate: resampled to 16 kHz). Not thread-safe (one decoder).
  VoiceCommand recognize(const AudioBuffer& audio);

  /// The JSGF grammar in use.
  const std::string& grammar() const;
  const std::vector<std::string>& places() const;
  const VoiceRecognizerConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Records `seconds` of 16 kHz mono audio from a capture device through sphinxad. Debian's
/// sphinxad is built on PulseAudio: `device` is a PulseAudio source name (empty: the default
/// source). Throws navaid::Error naming the device when it cannot be opened or read.
AudioBuffer record_from_device(const std::string& device, double seconds);

}  // namespace navaid::interaction
