#pragma once
// Helpers for the device adapter tests: cues of one kind, and what a pattern switches on.
#include <gtest/gtest.h>

#include <optional>
#include <set>

#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction::testing {

inline Cue cue_of(CueKind kind, Timestamp t = 1'000'000'000) {
  Cue c;
  c.t = t;
  c.kind = kind;
  c.priority = default_priority(kind);
  return c;
}

inline Cue walking_cue(CueKind kind, double direction_rad) {
  Cue c = cue_of(kind);
  c.direction_rad = direction_rad;
  return c;
}

/// The actuators a pattern lists (each at most once: a duplicate fails the test).
inline std::set<int> actuators_of(const ActuatorPattern& p) {
  std::set<int> s;
  for (const ActuatorCommand& c : p.commands) {
    EXPECT_TRUE(s.insert(c.actuator).second) << "actuator " << int(c.actuator) << " listed twice";
  }
  return s;
}

inline const ActuatorCommand* command_for(const ActuatorPattern& p, int actuator) {
  for (const ActuatorCommand& c : p.commands) {
    if (c.actuator == actuator) return &c;
  }
  return nullptr;
}

/// Every cue kind, for "cannot express" sweeps.
inline constexpr CueKind kAllKinds[] = {CueKind::kStop, CueKind::kObstacle, CueKind::kArrive, CueKind::kTurn,
                                        CueKind::kVeer, CueKind::kOnCourse, CueKind::kObjectDirection,
                                        CueKind::kSystem};

}  // namespace navaid::interaction::testing
