// What a recording lacks for a device, said before the run starts.
#include <gtest/gtest.h>

#include <string>

#include "navaid/experiments/device_requirements.hpp"
#include "test_support.hpp"

namespace {

using namespace navaid;
using namespace navaid::experiments;

TEST(DeviceRequirements, WhatARecordingLacksIsListed) {
  navaid::testing::ScratchDir dir("device-preset");
  const runtime::DeviceSpec spec = runtime::read_device_spec(Config::load(runtime::device_preset_file("elabrador")));
  io::Recording empty;
  const auto missing = missing_for_device(spec, empty, dir.path());
  std::string all;
  for (const auto& m : missing) all += m + "; ";
  EXPECT_NE(all.find("IMU samples"), std::string::npos) << all;
  EXPECT_NE(all.find("image frames"), std::string::npos) << all;
  EXPECT_NE(all.find("GPS fixes"), std::string::npos) << all;
  EXPECT_NE(all.find("device.route.osm"), std::string::npos) << all;  // not simulated: no streets of its own
}

}  // namespace
