#pragma once
// The rules that decide which cues reach the user and when, in one place, on a caller-driven
// clock (deterministic replay; real time is the same calls with the wall clock).
//
// Haptic channel (one device, through its DeviceAdapter):
//   - stop pre-empts at once and holds the device for stop_hold_s against lower cues;
//   - a cue more urgent than the one on the device is sent at once; other changes wait for the
//     device's refresh tick (eLabrador's belt: 1 Hz), so the device never chatters;
//   - the current cue is re-sent every refresh period while it is fresh (cue.ttl_s); a stale one
//     is switched off;
//   - a cue the device cannot express switches it off (the user must not feel an old direction).
// Speech channel (messages rendered by a SpeechRenderer, which knows their length):
//   - stop pre-empts at once: it interrupts the message in progress and drops what waits;
//   - a message at least interrupt_priority urgent and more urgent than the one in progress
//     interrupts it; otherwise it waits, most urgent first, until its time to live runs out;
//   - rate limits: stop at most once per stop_min_gap_s, "prepare to turn" once per
//     turn_min_gap_s (CaBot: 1 s and 5 s), hand directions once per hand_message_period_s (W-ROMA:
//     a voice command every 2 s), and at least speech_min_gap_s between the starts of two
//     messages (the Augmented Cane's 2.3 s) unless the later one interrupts;
//   - de-duplication: a message equal to the one in progress or waiting, or said within
//     duplicate_window_s, is dropped (hand directions and "repeat" requests excepted).
#include <array>
#include <cstddef>
#include <limits>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/cue.hpp"
#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction {

struct CuePolicyConfig {
  double stop_min_gap_s = 1.0;         ///< CaBot: stop at most once per second
  double turn_min_gap_s = 5.0;         ///< CaBot: a turn cue at most once per 5 s
  double hand_message_period_s = 2.0;  ///< W-ROMA: a voice command every two seconds
  double speech_min_gap_s = 2.3;       ///< the Augmented Cane: >= 2.3 s between messages
  double duplicate_window_s = 8.0;     ///< ours: the same words not again within 8 s
  int interrupt_priority = 80;         ///< obstacle and stop interrupt a message in progress
  double stop_hold_s = 1.0;            ///< ours: lower haptic cues wait this long after a stop
};

/// Keys interaction.policy.stop_min_gap_s, turn_min_gap_s, hand_message_period_s,
/// speech_min_gap_s, duplicate_window_s, stop_hold_s [0, 60], interrupt_priority [0, 1000].
CuePolicyConfig read_cue_policy_config(const Config& config);

/// Words and length of a message: templates plus synthesis (or text-only estimate).
class SpeechRenderer {
 public:
  virtual ~SpeechRenderer() = default;
  virtual std::string text(const SpokenMessage& message) const = 0;
  virtual double duration_s(const SpokenMessage& message, const std::string& text) const = 0;
};

enum class CueChannel { kHaptic, kSpeech };
std::string_view to_string(CueChannel channel);

enum class CueOutcome {
  kSent,         ///< haptic: a new pattern went to the device
  kRefreshed,    ///< haptic: the same pattern again at the refresh tick
  kSwitchedOff,  ///< haptic: the device was switched off (stale cue, inexpressible cue, stop guidance)
  kSpoken,       ///< speech: the message started
  kInterrupted,  ///< speech: the message in progress was cut off by a more urgent one
  kPreempted,    ///< speech: a waiting message was dropped because stop pre-empted it
  kRateLimited,  ///< dropped by a rate limit
  kDuplicate,    ///< dropped as a repetition
  kExpired,      ///< dropped: its time to live ran out before it could be delivered
  kFinished,     ///< speech: the message ended
};
std::string_view to_string(CueOutcome outcome);
constexpr std::size_t kCueOutcomeCount = 10;

struct CueEvent {
  Timestamp t = 0;
  CueChannel channel = CueChannel::kHaptic;
  CueOutcome outcome = CueOutcome::kSent;
  Cue cue;
  std::optional<ActuatorPattern> pattern;  ///< kSent, kRefreshed, kSwitchedOff
  std::string text;                        ///< speech events
  double duration_s = 0.0;                 ///< kSpoken: how long the message lasts
};

class CueScheduler {
 public:
  /// `speech` may be null: no speech channel (haptics only).
  CueScheduler(CuePolicyConfig policy, const DeviceAdapter& device, const SpeechRenderer* speech);

  /// Everything due up to and including `now` (refresh ticks, ends of messages, waiting messages
  /// starting), in time order. Call before push() with the cue's time, and whenever time passes.
  std::vector<CueEvent> advance(Timestamp now);
  /// Offers a cue at its time cue.t (>= the last advance time); returns what happened at once.
  std::vector<CueEvent> push(const Cue& cue);
  /// The next time advance() would produce something, if any.
  std::optional<Timestamp> next_due() const;

  /// Count of every outcome so far, indexed by CueOutcome.
  const std::array<std::size_t, kCueOutcomeCount>& counts() const { return counts_; }
  /// The message being spoken at the last advance time, if any.
  const std::optional<CueEvent>& speaking() const { return speaking_; }

 private:
  struct Waiting {
    Cue cue;
    Timestamp deadline;
  };
  void emit(std::vector<CueEvent>& out, CueEvent event);
  void haptic_push(const Cue& cue, std::vector<CueEvent>& out);
  void haptic_send(Timestamp t, const Cue& cue, bool refresh, std::vector<CueEvent>& out);
  void speech_push(const Cue& cue, std::vector<CueEvent>& out);
  void speech_start(Timestamp t, const Cue& cue, std::vector<CueEvent>& out);
  std::optional<Timestamp> haptic_due() const;
  std::optional<Timestamp> speech_due() const;
  Timestamp speech_start_time() const;  ///< needs a waiting message
  bool said_recently(const SpokenMessage& message, Timestamp t, double window_s) const;

  CuePolicyConfig policy_;
  const DeviceAdapter& device_;
  const SpeechRenderer* speech_;
  Timestamp now_ = std::numeric_limits<Timestamp>::min();
  std::array<std::size_t, kCueOutcomeCount> counts_{};

  // Haptic state: what is on the device, what should be next.
  std::optional<Cue> haptic_current_;
  std::optional<ActuatorPattern> haptic_pattern_;  ///< the pattern on the device (nullopt: off)
  std::optional<Timestamp> haptic_sent_at_;
  std::optional<Cue> haptic_next_;                 ///< waits for the tick or the end of a stop hold
  Timestamp stop_hold_until_ = std::numeric_limits<Timestamp>::min();

  // Speech state.
  std::optional<CueEvent> speaking_;
  Timestamp speaking_ends_ = 0;
  std::optional<Timestamp> last_start_;
  std::deque<Waiting> waiting_;
  std::map<std::string, Timestamp> last_said_;  ///< message key -> start time
  std::map<std::string, Timestamp> last_by_rule_;  ///< rate-limit rule -> start time
};

}  // namespace navaid::interaction
