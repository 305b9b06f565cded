// A narrated route as a guidance timeline: announcement times and distances at the walking speed,
// turn sides, crossings with their street, steps, arrival, and the config keys.
#include "navaid/interaction/route_timeline.hpp"

#include <gtest/gtest.h>

#include "navaid/core/errors.hpp"

namespace navaid::interaction {
namespace {

planning::Instruction instruction(planning::InstructionKind kind, double at_m, double turn_deg = 0.0,
                                  std::string road = {}) {
  planning::Instruction i;
  i.kind = kind;
  i.at_m = at_m;
  i.turn_deg = turn_deg;
  i.road = std::move(road);
  return i;
}

TEST(RouteTimeline, AnnouncementsComeAnnounceDistanceAheadAtTheWalkingSpeed) {
  using K = planning::InstructionKind;
  const std::vector<planning::Instruction> narration{
      instruction(K::kStart, 0.0),          instruction(K::kTurn, 8.0, -60.0),
      instruction(K::kTurn, 40.0, 75.0, "Fasanerieallee"), instruction(K::kCrossing, 70.0, 0.0, "Hauptstrasse"),
      instruction(K::kSteps, 100.0, 0.0, "ignored"),        instruction(K::kArrive, 130.0)};
  RouteTimelineConfig c;
  c.walk_speed_mps = 1.25;
  c.announce_m = 15.0;
  const auto t = route_timeline(narration, c);
  ASSERT_EQ(t.size(), 6u);
  EXPECT_EQ(std::get<SystemEvent>(t[0]).kind, SystemEventKind::kInitialized);
  const auto event = [&](std::size_t k) { return std::get<SystemEvent>(t[k]); };
  // The first turn is only 8 m away: announced at the start with its true distance.
  EXPECT_EQ(event(1).t, 0);
  EXPECT_EQ(event(1).value, "8;right");
  EXPECT_EQ(event(2).t, seconds_to_ns((40.0 - 15.0) / 1.25));
  EXPECT_EQ(event(2).value, "15;left;Fasanerieallee");
  EXPECT_EQ(event(3).value, "15;cross;Hauptstrasse");
  EXPECT_EQ(event(4).value, "15;steps");
  const auto& arrive = std::get<planning::GuidanceCommand>(t[5]);
  EXPECT_EQ(arrive.action, planning::GuidanceAction::kArrived);
  EXPECT_EQ(arrive.t, seconds_to_ns(130.0 / 1.25));
  for (std::size_t k = 1; k < t.size(); ++k) EXPECT_LE(entry_time(t[k - 1]), entry_time(t[k]));
}

TEST(RouteTimeline, KeysAreRangeChecked) {
  const auto c = read_route_timeline_config(Config::parse("{}", "t", {"interaction.route.walk_speed_mps=1.4"}));
  EXPECT_DOUBLE_EQ(c.walk_speed_mps, 1.4);
  EXPECT_DOUBLE_EQ(c.announce_m, 15.0);
  EXPECT_THROW(read_route_timeline_config(Config::parse("{}", "t", {"interaction.route.walk_speed_mps=0"})), ConfigError);
  EXPECT_THROW(read_route_timeline_config(Config::parse("{}", "t", {"interaction.route.announce_m=-1"})), ConfigError);
  RouteTimelineConfig bad;
  bad.walk_speed_mps = 0.0;
  EXPECT_THROW(route_timeline({}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
