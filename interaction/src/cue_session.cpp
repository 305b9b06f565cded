#include "navaid/interaction/cue_session.hpp"

#include <algorithm>

namespace navaid::interaction {

CueSession::CueSession(CueGeneratorConfig generator, CuePolicyConfig policy, const DeviceAdapter& device,
                       const SpeechRenderer* speech, Sink sink)
    : generator_(generator), scheduler_(policy, device, speech), sink_(std::move(sink)) {}

std::vector<CueEvent> CueSession::keep(std::vector<CueEvent> events) {
  for (const CueEvent& e : events) {
    if (sink_) sink_(e);
    events_.push_back(e);
  }
  return events;
}

std::vector<CueEvent> CueSession::advance(Timestamp t) {
  now_ = std::max(now_, t);
  return keep(scheduler_.advance(t));
}

std::vector<CueEvent> CueSession::feed(const GuidanceTimelineEntry& entry) {
  const Timestamp t = entry_time(entry);
  std::vector<CueEvent> out = advance(t);
  const std::vector<Cue> cues = std::holds_alternative<planning::GuidanceCommand>(entry)
                                    ? generator_.on_guidance(std::get<planning::GuidanceCommand>(entry))
                                    : generator_.on_event(std::get<SystemEvent>(entry));
  for (const Cue& cue : cues) {
    for (CueEvent& e : keep(scheduler_.push(cue))) out.push_back(std::move(e));
  }
  return out;
}

std::vector<CueEvent> CueSession::drain(double limit_s) {
  const Timestamp end = now_ + seconds_to_ns(limit_s);
  std::vector<CueEvent> out;
  while (const std::optional<Timestamp> due = scheduler_.next_due()) {
    if (*due > end) break;
    for (CueEvent& e : advance(*due)) out.push_back(std::move(e));
  }
  return out;
}

}  // namespace navaid::interaction
