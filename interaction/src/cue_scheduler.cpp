#include "navaid/interaction/cue_scheduler.hpp"

#include <algorithm>

#include "navaid/core/enum_names.hpp"
#include "navaid/interaction/config_schema.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<CueChannel, 2> kChannelNames{{
    {CueChannel::kHaptic, "haptic"},
    {CueChannel::kSpeech, "speech"},
}};

constexpr NameTable<CueOutcome, kCueOutcomeCount> kOutcomeNames{{
    {CueOutcome::kSent, "sent"},
    {CueOutcome::kRefreshed, "refreshed"},
    {CueOutcome::kSwitchedOff, "switched-off"},
    {CueOutcome::kSpoken, "spoken"},
    {CueOutcome::kInterrupted, "interrupted"},
    {CueOutcome::kPreempted, "preempted"},
    {CueOutcome::kRateLimited, "rate-limited"},
    {CueOutcome::kDuplicate, "duplicate"},
    {CueOutcome::kExpired, "expired"},
    {CueOutcome::kFinished, "finished"},
}};

bool is_haptic(CueKind kind) { return kind != CueKind::kSystem; }

std::string message_key(const SpokenMessage& m) {
  std::string key(to_string(m.category));
  key += '/';
  key += m.id;
  for (const auto& [name, value] : m.args) key += '|' + name + '=' + value;
  return key;
}

bool same_commands(const ActuatorPattern& a, const ActuatorPattern& b) {
  if (a.device != b.device || a.commands.size() != b.commands.size()) return false;
  for (std::size_t i = 0; i < a.commands.size(); ++i) {
    const ActuatorCommand& x = a.commands[i];
    const ActuatorCommand& y = b.commands[i];
    if (x.actuator != y.actuator || x.level != y.level || x.on_ms != y.on_ms || x.off_ms != y.off_ms ||
        x.hold_ms != y.hold_ms) {
      return false;
    }
  }
  return true;
}

Timestamp after(Timestamp t, double seconds) { return t + seconds_to_ns(seconds); }

}  // namespace

std::string_view to_string(CueChannel channel) { return enum_name(kChannelNames, channel); }
std::string_view to_string(CueOutcome outcome) { return enum_name(kOutcomeNames, outcome); }

namespace {
const CuePolicyConfig kCueSchedulerDefaults;
constexpr Range kSeconds{0.0, 60.0};
const ConfigKey<double> kStopMinGap{"interaction.policy.stop_min_gap_s", kCueSchedulerDefaults.stop_min_gap_s, kSeconds,
                                    "a stop cue at most once per this [s] (CaBot: 1)"};
const ConfigKey<double> kTurnMinGap{"interaction.policy.turn_min_gap_s", kCueSchedulerDefaults.turn_min_gap_s, kSeconds,
                                    "a turn cue at most once per this [s] (CaBot: 5)"};
const ConfigKey<double> kHandMessagePeriod{"interaction.policy.hand_message_period_s", kCueSchedulerDefaults.hand_message_period_s,
                                           kSeconds, "a hand-guidance message at most once per this [s] (W-ROMA: 2)"};
const ConfigKey<double> kSpeechMinGap{"interaction.policy.speech_min_gap_s", kCueSchedulerDefaults.speech_min_gap_s, kSeconds,
                                      "least time between two spoken messages [s] (the Augmented Cane: 2.3)"};
const ConfigKey<double> kDuplicateWindow{"interaction.policy.duplicate_window_s", kCueSchedulerDefaults.duplicate_window_s, kSeconds,
                                         "the same words are not spoken again within this [s]"};
const ConfigKey<double> kStopHold{"interaction.policy.stop_hold_s", kCueSchedulerDefaults.stop_hold_s, kSeconds,
                                  "lower haptic cues wait this long after a stop [s]"};
const ConfigKey<int> kInterruptPriority{"interaction.policy.interrupt_priority", kCueSchedulerDefaults.interrupt_priority, 0, 1000,
                                        "cues of at least this priority interrupt a message in progress"};
}  // namespace

ConfigSchema cue_policy_config_schema() {
  return ConfigSchema()
      .add(kStopMinGap)
      .add(kTurnMinGap)
      .add(kHandMessagePeriod)
      .add(kSpeechMinGap)
      .add(kDuplicateWindow)
      .add(kStopHold)
      .add(kInterruptPriority);
}

CuePolicyConfig read_cue_policy_config(const Config& config) {
  CuePolicyConfig c;
  c.stop_min_gap_s = get(config, kStopMinGap);
  c.turn_min_gap_s = get(config, kTurnMinGap);
  c.hand_message_period_s = get(config, kHandMessagePeriod);
  c.speech_min_gap_s = get(config, kSpeechMinGap);
  c.duplicate_window_s = get(config, kDuplicateWindow);
  c.stop_hold_s = get(config, kStopHold);
  c.interrupt_priority = get(config, kInterruptPriority);
  return c;
}

CueScheduler::CueScheduler(CuePolicyConfig policy, const DeviceAdapter& device, const SpeechRenderer* speech)
    : policy_(policy), device_(device), speech_(speech) {}

void CueScheduler::emit(std::vector<CueEvent>& out, CueEvent event) {
  ++counts_[static_cast<std::size_t>(event.outcome)];
  out.push_back(std::move(event));
}

// ---- haptic channel ----

void CueScheduler::haptic_send(Timestamp t, const Cue& cue, bool refresh, std::vector<CueEvent>& out) {
  std::optional<ActuatorPattern> pattern = device_.pattern(cue);
  haptic_current_ = cue;
  haptic_sent_at_ = t;
  if (!pattern) {
    // The device cannot say this: it must not keep saying the previous thing.
    if (haptic_pattern_) {
      haptic_pattern_.reset();
      emit(out, {t, CueChannel::kHaptic, CueOutcome::kSwitchedOff, cue, device_.all_off(t), {}, 0.0});
    }
    return;
  }
  pattern->t = t;
  const bool same = haptic_pattern_ && same_commands(*haptic_pattern_, *pattern);
  haptic_pattern_ = pattern;
  emit(out, {t, CueChannel::kHaptic, refresh && same ? CueOutcome::kRefreshed : CueOutcome::kSent, cue,
             std::move(pattern), {}, 0.0});
}

void CueScheduler::haptic_push(const Cue& cue, std::vector<CueEvent>& out) {
  const Timestamp t = cue.t;
  if (cue.clear_haptics) {
    haptic_next_.reset();
    haptic_current_.reset();
    stop_hold_until_ = std::numeric_limits<Timestamp>::min();
    if (haptic_pattern_) {
      haptic_pattern_.reset();
      emit(out, {t, CueChannel::kHaptic, CueOutcome::kSwitchedOff, cue, device_.all_off(t), {}, 0.0});
    }
    return;
  }
  if (!is_haptic(cue.kind) || !cue.felt) return;
  if (cue.kind == CueKind::kStop) {
    haptic_next_.reset();
    stop_hold_until_ = after(t, policy_.stop_hold_s);
    if (haptic_current_ && haptic_current_->kind == CueKind::kStop && haptic_pattern_) {
      haptic_current_ = cue;  // still stopping: keep it fresh, the refresh tick re-sends it
      return;
    }
    haptic_send(t, cue, false, out);
    return;
  }
  if (t < stop_hold_until_) {
    haptic_next_ = cue;
    return;
  }
  const bool stale = haptic_current_ && t > after(haptic_current_->t, haptic_current_->ttl_s);
  if (!haptic_current_ || !haptic_pattern_ || stale || cue.priority > haptic_current_->priority) {
    haptic_next_.reset();
    haptic_send(t, cue, false, out);
    return;
  }
  const std::optional<ActuatorPattern> pattern = device_.pattern(cue);
  if (pattern && same_commands(*pattern, *haptic_pattern_)) {
    haptic_current_ = cue;  // the same feel, fresher cause
    haptic_next_.reset();
  } else {
    haptic_next_ = cue;  // a change of equal or lower urgency waits for the device's tick
  }
}

std::optional<Timestamp> CueScheduler::haptic_due() const {
  const std::optional<Timestamp> tick =
      haptic_pattern_ && haptic_sent_at_ ? std::optional(after(*haptic_sent_at_, device_.refresh_period_s()))
                                         : std::nullopt;
  if (haptic_next_) return std::max(stop_hold_until_, tick.value_or(haptic_next_->t));
  return tick;
}

// ---- speech channel ----

bool CueScheduler::said_recently(const SpokenMessage& message, Timestamp t, double window_s) const {
  const auto it = last_said_.find(message_key(message));
  return it != last_said_.end() && t < after(it->second, window_s);
}

namespace {

/// The rate-limit rule of a message: its minimum gap [s] from the previous one of the same id.
std::optional<double> rule_gap(const SpokenMessage& m, const CuePolicyConfig& p) {
  if (m.id == "stop") return p.stop_min_gap_s;
  if (m.id == "prepare_turn") return p.turn_min_gap_s;
  if (m.id == "move_hand") return p.hand_message_period_s;
  return std::nullopt;
}

}  // namespace

void CueScheduler::speech_start(Timestamp t, const Cue& cue, std::vector<CueEvent>& out) {
  const SpokenMessage& m = *cue.message;
  std::string text = speech_->text(m);
  const double duration = speech_->duration_s(m, text);
  last_start_ = t;
  last_said_[message_key(m)] = t;
  if (rule_gap(m, policy_)) last_by_rule_[m.id] = t;
  CueEvent event{t, CueChannel::kSpeech, CueOutcome::kSpoken, cue, std::nullopt, std::move(text), duration};
  speaking_ = event;
  speaking_ends_ = after(t, duration);
  emit(out, std::move(event));
}

void CueScheduler::speech_push(const Cue& cue, std::vector<CueEvent>& out) {
  if (!speech_ || !cue.message) return;
  const Timestamp t = cue.t;
  const SpokenMessage& m = *cue.message;
  const std::string key = message_key(m);
  const auto drop = [&](CueOutcome why) { emit(out, {t, CueChannel::kSpeech, why, cue, std::nullopt, {}, 0.0}); };

  if (const std::optional<double> gap = rule_gap(m, policy_)) {
    const auto last = last_by_rule_.find(m.id);
    if (last != last_by_rule_.end() && t < after(last->second, *gap)) return drop(CueOutcome::kRateLimited);
    // A newer one of a rate-limited kind replaces a waiting older one (a fresher hand direction).
    for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
      if (it->cue.message->id == m.id) {
        emit(out, {t, CueChannel::kSpeech, CueOutcome::kDuplicate, it->cue, std::nullopt, {}, 0.0});
        waiting_.erase(it);
        break;
      }
    }
  } else if (!cue.repeat) {
    const bool in_progress = speaking_ && message_key(*speaking_->cue.message) == key;
    const bool queued = std::any_of(waiting_.begin(), waiting_.end(),
                                    [&](const Waiting& w) { return message_key(*w.cue.message) == key; });
    if (in_progress || queued || said_recently(m, t, policy_.duplicate_window_s)) return drop(CueOutcome::kDuplicate);
  }

  const bool stop = cue.kind == CueKind::kStop;
  const bool interrupts = speaking_ && (stop || (cue.priority >= policy_.interrupt_priority &&
                                                 cue.priority > speaking_->cue.priority));
  if (interrupts) {
    CueEvent cut = *speaking_;
    cut.t = t;
    cut.outcome = CueOutcome::kInterrupted;
    speaking_.reset();
    emit(out, std::move(cut));
  }
  if (stop) {
    // Everything less urgent that waits was about a situation that no longer holds.
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      if (it->cue.priority < cue.priority) {
        emit(out, {t, CueChannel::kSpeech, CueOutcome::kPreempted, it->cue, std::nullopt, {}, 0.0});
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
  }
  const bool gap_ok = !last_start_ || t >= after(*last_start_, policy_.speech_min_gap_s);
  if (interrupts || (stop && !speaking_) || (!speaking_ && gap_ok && waiting_.empty())) {
    speech_start(t, cue, out);
    return;
  }
  // Most urgent first, then oldest first.
  const auto pos = std::find_if(waiting_.begin(), waiting_.end(),
                                [&](const Waiting& w) { return w.cue.priority < cue.priority; });
  waiting_.insert(pos, Waiting{cue, after(t, cue.ttl_s)});
}

Timestamp CueScheduler::speech_start_time() const {
  const Timestamp first = waiting_.front().cue.t;
  return last_start_ ? std::max(after(*last_start_, policy_.speech_min_gap_s), first) : first;
}

std::optional<Timestamp> CueScheduler::speech_due() const {
  if (speaking_) return speaking_ends_;
  if (waiting_.empty()) return std::nullopt;
  Timestamp due = speech_start_time();
  for (const Waiting& w : waiting_) due = std::min(due, w.deadline);
  return due;
}

// ---- both ----

std::optional<Timestamp> CueScheduler::next_due() const {
  const std::optional<Timestamp> h = haptic_due();
  const std::optional<Timestamp> s = speech_due();
  if (h && s) return std::min(*h, *s);
  return h ? h : s;
}

std::vector<CueEvent> CueScheduler::advance(Timestamp now) {
  std::vector<CueEvent> out;
  for (;;) {
    const std::optional<Timestamp> h = haptic_due();
    const std::optional<Timestamp> s = speech_due();
    const bool haptic_first = h && *h <= now && (!s || *h <= *s);
    const bool speech_first = !haptic_first && s && *s <= now;
    if (!haptic_first && !speech_first) break;
    if (haptic_first) {
      const Timestamp t = *h;
      if (haptic_next_) {
        const Cue next = *haptic_next_;
        haptic_next_.reset();
        haptic_send(t, next, true, out);
      } else if (haptic_current_->kind == CueKind::kArrive) {
        // Arrival is a one-shot pattern that ends by its own hold: felt once, not every tick.
        haptic_pattern_.reset();
        haptic_current_.reset();
      } else if (t > after(haptic_current_->t, haptic_current_->ttl_s)) {
        // Stale: the planner has not confirmed this direction for a while; say nothing rather
        // than something old.
        haptic_pattern_.reset();
        emit(out, {t, CueChannel::kHaptic, CueOutcome::kSwitchedOff, *haptic_current_, device_.all_off(t), {}, 0.0});
        haptic_current_.reset();
      } else {
        haptic_send(t, *haptic_current_, true, out);
      }
      continue;
    }
    const Timestamp t = *s;
    if (speaking_) {
      CueEvent done = *speaking_;
      done.t = t;
      done.outcome = CueOutcome::kFinished;
      speaking_.reset();
      emit(out, std::move(done));
      continue;
    }
    // Drop what can no longer start in time, then start the most urgent.
    const Timestamp start = speech_start_time();
    bool dropped = false;
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      if (it->deadline < start && it->deadline <= t) {
        emit(out, {it->deadline, CueChannel::kSpeech, CueOutcome::kExpired, it->cue, std::nullopt, {}, 0.0});
        it = waiting_.erase(it);
        dropped = true;
      } else {
        ++it;
      }
    }
    if (dropped || t < start) continue;
    const Cue cue = waiting_.front().cue;
    waiting_.pop_front();
    speech_start(t, cue, out);
  }
  now_ = std::max(now_, now);
  return out;
}

std::vector<CueEvent> CueScheduler::push(const Cue& cue) {
  std::vector<CueEvent> out = advance(cue.t);
  haptic_push(cue, out);
  speech_push(cue, out);
  return out;
}

}  // namespace navaid::interaction
