#pragma once
// One user's interaction over a guidance timeline: generator -> scheduler -> device adapter, on
// the timeline's clock, with every cue event kept. `navaid cues` and the full-device runs use it;
// a sink sees each event as it happens (the device link sends patterns from there).
#include <functional>
#include <memory>
#include <vector>

#include "navaid/interaction/cue_generator.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/device_adapter.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"

namespace navaid::interaction {

class CueSession {
 public:
  using Sink = std::function<void(const CueEvent&)>;

  /// `speech` may be null (haptics only); it must outlive the session, as must `device`.
  CueSession(CueGeneratorConfig generator, CuePolicyConfig policy, const DeviceAdapter& device,
             const SpeechRenderer* speech, Sink sink = {});

  /// Feeds one timeline entry (times must not decrease); returns the events it caused.
  std::vector<CueEvent> feed(const GuidanceTimelineEntry& entry);
  /// Lets time pass to `t` (refresh ticks, messages ending and starting).
  std::vector<CueEvent> advance(Timestamp t);
  /// Runs until nothing is due any more (at most `limit_s` after the last entry).
  std::vector<CueEvent> drain(double limit_s = 30.0);

  const CueScheduler& scheduler() const { return scheduler_; }
  const std::vector<CueEvent>& events() const { return events_; }

 private:
  std::vector<CueEvent> keep(std::vector<CueEvent> events);

  CueGenerator generator_;
  CueScheduler scheduler_;
  Sink sink_;
  std::vector<CueEvent> events_;
  Timestamp now_ = 0;
};

}  // namespace navaid::interaction
