// map_server occupancy maps: the real Willow Garage office map, and every way a map file can be
// wrong giving an error that names the file and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "navaid/core/errors.hpp"
#include "navaid/io/occupancy_map_file.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

using testing::ScratchDir;
using testing::error_message;
using testing::write_text;

TEST(OccupancyMapFile, ReadsTheRealWillowOfficeMap) {
  NAVAID_REQUIRE_SHARED_DATA();
  const OccupancyMapFile m = read_occupancy_map(testing::shared_data_dir() / "ros-map-willow/willow-full-0.05.yaml");
  EXPECT_EQ(m.image.width, 962);
  EXPECT_EQ(m.image.height, 1088);
  EXPECT_DOUBLE_EQ(m.resolution_m, 0.05);
  EXPECT_FALSE(m.negate);
  std::size_t counts[3] = {0, 0, 0};
  std::size_t white = 0, grey204 = 0, black = 0;
  for (int y = 0; y < m.image.height; ++y)
    for (int x = 0; x < m.image.width; ++x) {
      ++counts[static_cast<int>(m.cell(x, y))];
      white += m.image.at(x, y) == 255;
      grey204 += m.image.at(x, y) == 204;
      black += m.image.at(x, y) == 0;
    }
  // SOURCE.md: 255 free (519,712 px), 204 unknown (487,212), 0 occupied (10,907), a few greys.
  EXPECT_EQ(white, 519712U);
  EXPECT_EQ(grey204, 487212U);
  EXPECT_EQ(black, 10907U);
  EXPECT_GE(counts[static_cast<int>(OccupancyCell::kFree)], white);
  EXPECT_GE(counts[static_cast<int>(OccupancyCell::kUnknown)], grey204);  // p = 0.2 lies between the thresholds
  EXPECT_GE(counts[static_cast<int>(OccupancyCell::kOccupied)], black);
  EXPECT_EQ(counts[0] + counts[1] + counts[2], 962U * 1088U);
}

class OccupancyMapFileErrors : public ::testing::Test {
 protected:
  OccupancyMapFileErrors() : dir_("occupancy-map-errors") {
    std::ofstream(dir_ / "map.pgm", std::ios::binary) << "P5\n4 3\n255\n" << std::string(12, '\xff');
  }
  std::filesystem::path yaml(const std::string& text) {
    write_text(dir_ / "map.yaml", text);
    return dir_ / "map.yaml";
  }
  ScratchDir dir_;
};

constexpr const char* kGood =
    "image: map.pgm\nresolution: 0.1\norigin: [-1.0, 2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
    "free_thresh: 0.196\n";

TEST_F(OccupancyMapFileErrors, AGoodSmallMapReads) {
  const OccupancyMapFile m = read_occupancy_map(yaml(kGood));
  EXPECT_EQ(m.image.width, 4);
  EXPECT_DOUBLE_EQ(m.origin_x_m, -1.0);
  EXPECT_EQ(m.cell(0, 0), OccupancyCell::kFree);
  const OccupancyMapFile with_mode = read_occupancy_map(yaml(std::string(kGood) + "mode: trinary\n"));
  EXPECT_EQ(with_mode.mode, "trinary");
}

TEST_F(OccupancyMapFileErrors, EveryBrokenFieldNamesItsKey) {
  const auto message = [&](const std::string& text) {
    return error_message<Error>([&] { read_occupancy_map(yaml(text)); });
  };
  EXPECT_NE(message("resolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n").find("image"),
            std::string::npos);
  EXPECT_NE(message("image: map.pgm\nresolution: -1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n")
                .find("resolution"),
            std::string::npos);
  EXPECT_NE(message("image: map.pgm\nresolution: 0.1\norigin: [0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n")
                .find("origin"),
            std::string::npos);
  EXPECT_NE(message("image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.1\nfree_thresh: 0.2\n")
                .find("free_thresh"),
            std::string::npos);
  EXPECT_NE(message("image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 1.5\nfree_thresh: 0.2\n")
                .find("occupied_thresh"),
            std::string::npos);
  EXPECT_NE(message(std::string(kGood) + "mode: raw\n").find("mode"), std::string::npos);
  EXPECT_NE(message("image: missing.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n")
                .find("missing.pgm"),
            std::string::npos);
  EXPECT_NE(message("- just\n- a list\n").find("mapping"), std::string::npos);
  EXPECT_NE(message("image: [unclosed\n").find("map.yaml"), std::string::npos);
  // A truncated image (header promises 4 x 3, two bytes follow).
  std::ofstream(dir_ / "map.pgm", std::ios::binary | std::ios::trunc) << "P5\n4 3\n255\n" << std::string(2, '\0');
  EXPECT_NE(message(kGood).find("map.pgm"), std::string::npos);
  EXPECT_THROW(read_occupancy_map(dir_ / "nothing.yaml"), IoError);
}

}  // namespace
}  // namespace navaid::io
