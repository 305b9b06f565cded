// open_input: the input kinds' names (to_string, and input_kind_from_string behind --format).
#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <vector>

#include "navaid/io/open_input.hpp"

namespace navaid::io {
namespace {

TEST(InputKindNames, EveryKindHasItsNameAndFormatsRoundTrip) {
  // Every enumerator with its name; a dropped or misspelt table entry fails.
  const std::vector<std::pair<InputKind, std::string_view>> kinds{
      {InputKind::kNavaidRecording, "navaid"},
      {InputKind::kEuroc, "euroc"},
      {InputKind::kTumRgbd, "tum-rgbd"},
      {InputKind::kNmeaCapture, "nmea"},
      {InputKind::kTumTrajectory, "tum-trajectory"},
      {InputKind::kRosBag, "ros-bag"},
      {InputKind::kCollection, "collection"},
  };
  for (const auto& [kind, name] : kinds) {
    EXPECT_EQ(to_string(kind), name);
    if (kind == InputKind::kCollection) continue;
    EXPECT_EQ(input_kind_from_string(name), kind) << name;
    EXPECT_EQ(input_kind_from_string(to_string(kind)), kind) << name;
  }
}

TEST(InputKindNames, CollectionIsDetectedNeverForced) {
  EXPECT_EQ(input_kind_from_string("collection"), std::nullopt);
}

TEST(InputKindNames, UnknownNameAndValue) {
  EXPECT_EQ(input_kind_from_string("rosbag"), std::nullopt);
  EXPECT_EQ(input_kind_from_string("EuRoC"), std::nullopt);
  EXPECT_EQ(input_kind_from_string(""), std::nullopt);
  EXPECT_EQ(to_string(static_cast<InputKind>(99)), "unknown");
}

}  // namespace
}  // namespace navaid::io
