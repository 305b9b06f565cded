// The guidance timeline CSV: round trip, and every malformed input a clear error with its line.
#include "navaid/interaction/guidance_timeline_csv.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

const std::string kHeader = "t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n";

std::vector<GuidanceTimelineEntry> parse(const std::string& text) {
  std::istringstream in(text);
  return parse_guidance_timeline_csv(in, "timeline.csv");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(GuidanceTimelineCsv, ReadsGuidanceAndEvents) {
  const auto entries = parse(kHeader +
                             "# a comment\n"
                             "0.0,event,,,,,,,,initialized,\n"
                             "0.1,guidance,go,path-found,0.9,12.5,-3,,,,\n"
                             "\n"
                             "0.2,guidance,go,obstacle-ahead,1,,,left,,,\n"
                             "0.3,guidance,go,target-in-view,1,,,,up-left,,\n"
                             "0.4,guidance,stop,obstacle-ahead,1,,,,,,\n"
                             "0.5,event,,,,,,,,voice_command,\"go to kitchen, please\"\n");
  ASSERT_EQ(entries.size(), 6u);
  EXPECT_EQ(std::get<SystemEvent>(entries[0]).kind, SystemEventKind::kInitialized);
  const auto& go = std::get<planning::GuidanceCommand>(entries[1]);
  EXPECT_EQ(go.t, seconds_to_ns(0.1));
  EXPECT_EQ(go.action, planning::GuidanceAction::kGo);
  EXPECT_DOUBLE_EQ(go.confidence, 0.9);
  EXPECT_NEAR(*go.heading_rad, planning::deg_to_rad(12.5), 1e-12);
  EXPECT_NEAR(*go.steering_rad, planning::deg_to_rad(-3.0), 1e-12);
  EXPECT_EQ(*std::get<planning::GuidanceCommand>(entries[2]).rumble, planning::RumbleState::kLeft);
  EXPECT_EQ(*std::get<planning::GuidanceCommand>(entries[3]).hand, planning::HandDirection::kUpLeft);
  EXPECT_EQ(std::get<SystemEvent>(entries[5]).value, "go to kitchen, please");
}

TEST(GuidanceTimelineCsv, WriteThenReadGivesTheSameEntries) {
  planning::GuidanceCommand c;
  c.t = seconds_to_ns(1.25);
  c.action = planning::GuidanceAction::kGo;
  c.reason = planning::GuidanceReason::kPathFound;
  c.confidence = 0.75;
  c.heading_rad = 0.3;
  c.rumble = planning::RumbleState::kBoth;
  const std::vector<GuidanceTimelineEntry> entries = {
      SystemEvent{0, SystemEventKind::kEstimatorMode, "RGBD-VIO"}, c,
      SystemEvent{seconds_to_ns(2.0), SystemEventKind::kRouteInstruction, "49;left;Main \"High\" Street, north"}};
  const navaid::testing::ScratchDir dir("guidance_timeline");
  const std::filesystem::path file = dir / "timeline.csv";
  write_guidance_timeline_csv(file, entries);
  const auto back = read_guidance_timeline_csv(file);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(std::get<SystemEvent>(back[0]).value, "RGBD-VIO");
  const auto& c2 = std::get<planning::GuidanceCommand>(back[1]);
  EXPECT_EQ(c2.t, c.t);
  EXPECT_NEAR(*c2.heading_rad, 0.3, 1e-9);
  EXPECT_EQ(*c2.rumble, planning::RumbleState::kBoth);
  EXPECT_EQ(std::get<SystemEvent>(back[2]).value, "49;left;Main \"High\" Street, north");
}

TEST(GuidanceTimelineCsv, ReadsEveryNameOfTheGuidanceEnumsAndEvents) {
  // Each enumerator spelt out as the file has it; a name planning or interaction dropped or
  // misspelt from its table fails here.
  const std::vector<std::pair<std::string, planning::GuidanceAction>> actions{
      {"go", planning::GuidanceAction::kGo},
      {"stop", planning::GuidanceAction::kStop},
      {"wait", planning::GuidanceAction::kWait},
      {"arrived", planning::GuidanceAction::kArrived},
  };
  for (const auto& [name, action] : actions) {
    const auto e = parse(kHeader + "0," + "guidance," + name + ",locating,0,0,,,,,\n");
    EXPECT_EQ(std::get<planning::GuidanceCommand>(e.at(0)).action, action) << name;
  }
  const std::vector<std::pair<std::string, planning::GuidanceReason>> reasons{
      {"path-found", planning::GuidanceReason::kPathFound},
      {"obstacle-ahead", planning::GuidanceReason::kObstacleAhead},
      {"no-path", planning::GuidanceReason::kNoPath},
      {"search-limit", planning::GuidanceReason::kSearchLimit},
      {"start-blocked", planning::GuidanceReason::kStartBlocked},
      {"goal-blocked", planning::GuidanceReason::kGoalBlocked},
      {"off-map", planning::GuidanceReason::kOffMap},
      {"locating", planning::GuidanceReason::kLocating},
      {"registration-uncertain", planning::GuidanceReason::kRegistrationUncertain},
      {"target-not-seen", planning::GuidanceReason::kTargetNotSeen},
      {"target-far", planning::GuidanceReason::kTargetFar},
      {"target-reached", planning::GuidanceReason::kTargetReached},
      {"target-in-view", planning::GuidanceReason::kTargetInView},
      {"target-remembered", planning::GuidanceReason::kTargetRemembered},
  };
  for (const auto& [name, reason] : reasons) {
    const auto e = parse(kHeader + "0,guidance,wait," + name + ",0,,,,,,\n");
    EXPECT_EQ(std::get<planning::GuidanceCommand>(e.at(0)).reason, reason) << name;
  }
  const std::vector<std::pair<std::string, planning::RumbleState>> rumbles{
      {"off", planning::RumbleState::kOff},
      {"left", planning::RumbleState::kLeft},
      {"right", planning::RumbleState::kRight},
      {"both", planning::RumbleState::kBoth},
  };
  for (const auto& [name, rumble] : rumbles) {
    const auto e = parse(kHeader + "0,guidance,go,obstacle-ahead,1,,," + name + ",,,\n");
    EXPECT_EQ(std::get<planning::GuidanceCommand>(e.at(0)).rumble, rumble) << name;
  }
  const std::vector<std::pair<std::string, planning::HandDirection>> hands{
      {"hold", planning::HandDirection::kHold},
      {"right", planning::HandDirection::kRight},
      {"up-right", planning::HandDirection::kUpRight},
      {"up", planning::HandDirection::kUp},
      {"up-left", planning::HandDirection::kUpLeft},
      {"left", planning::HandDirection::kLeft},
      {"down-left", planning::HandDirection::kDownLeft},
      {"down", planning::HandDirection::kDown},
      {"down-right", planning::HandDirection::kDownRight},
      {"forward", planning::HandDirection::kForward},
      {"backward", planning::HandDirection::kBackward},
  };
  for (const auto& [name, hand] : hands) {
    const auto e = parse(kHeader + "0,guidance,go,target-in-view,1,,,," + name + ",,\n");
    EXPECT_EQ(std::get<planning::GuidanceCommand>(e.at(0)).hand, hand) << name;
  }
  const std::vector<std::pair<std::string, SystemEventKind>> events{
      {"initialized", SystemEventKind::kInitialized},
      {"estimator_mode", SystemEventKind::kEstimatorMode},
      {"network_lost", SystemEventKind::kNetworkLost},
      {"network_restored", SystemEventKind::kNetworkRestored},
      {"link_lost", SystemEventKind::kLinkLost},
      {"link_restored", SystemEventKind::kLinkRestored},
      {"camera_fault", SystemEventKind::kCameraFault},
      {"voice_command", SystemEventKind::kVoiceCommand},
      {"route_instruction", SystemEventKind::kRouteInstruction},
  };
  for (const auto& [name, kind] : events) {
    EXPECT_EQ(to_string(kind), name);
    EXPECT_EQ(system_event_kind_from_string(to_string(kind)), kind) << name;
    const auto e = parse(kHeader + "0,event,,,,,,,," + name + ",\n");
    EXPECT_EQ(std::get<SystemEvent>(e.at(0)).kind, kind) << name;
  }
}

TEST(GuidanceTimelineCsv, MalformedInputIsAClearErrorWithItsLine) {
  EXPECT_NE(error_of("").find("empty file"), std::string::npos);
  EXPECT_NE(error_of("t,x,y\n").find("not a guidance timeline header"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0.0,guidance,go\n").find("3 fields"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "abc,event,,,,,,,,initialized,\n").find("t_s"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "1,event,,,,,,,,initialized,\n0.5,event,,,,,,,,initialized,\n").find("backwards"),
            std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,run,path-found,1,0,,,,,\n").find("action"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,because,1,0,,,,,\n").find("reason"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1.5,0,,,,,\n").find("confidence"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1,nan,,,,,\n").find("heading_deg"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1,12x,,,,,\n").find("heading_deg"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1,,,,,,\n").find("needs heading_deg"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1,,,sideways,,,\n").find("rumble"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,guidance,go,path-found,1,,,,north,,\n").find("hand"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,event,,,,,,,,explosion,\n").find("unknown event"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,banner,,,,,,,,,\n").find("type"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,event,,,,,,,,voice_command,\"open\n").find("unterminated"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0,event,,,,,,,,initialized,\n0,event,,,,,,,,initialized,\n0,banner,,,,,,,,,\n")
                .find(":4"),
            std::string::npos);
  EXPECT_THROW(read_guidance_timeline_csv("/nonexistent/timeline.csv"), IoError);
}

}  // namespace
}  // namespace navaid::interaction
