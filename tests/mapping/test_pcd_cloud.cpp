// The PCD reader on PCL's real test clouds and on broken files.
#include "navaid/mapping/pcd_cloud.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

std::filesystem::path pcd_fixture(const std::string& name) { return testing::shared_data_dir() / "pcl-clouds" / name; }

std::size_t count_finite(const PcdCloud& c) {
  return static_cast<std::size_t>(std::count_if(c.points.begin(), c.points.end(), [](const Eigen::Vector3f& p) { return p.allFinite(); }));
}

// The IoError of reading `file`, which must name it.
void expect_io_error_naming(const std::filesystem::path& file) {
  const auto e = testing::expect_throw<IoError>([&] { read_pcd_cloud(file); }, file.string());
  if (!e) return;
  EXPECT_EQ(e->file(), file.string());
  EXPECT_NE(std::string(e->what()).find(file.string()), std::string::npos) << e->what();
}

TEST(PcdCloud, OrganizedKinectCloudKeepsItsLayout) {
  NAVAID_REQUIRE_SHARED_DATA();
  const PcdCloud c = read_pcd_cloud(pcd_fixture("five_people.pcd"));
  EXPECT_EQ(c.width, 640u);
  EXPECT_EQ(c.height, 480u);
  EXPECT_TRUE(c.organized());
  ASSERT_EQ(c.points.size(), 640u * 480u);
  EXPECT_FALSE(c.is_dense);
  const std::size_t finite = count_finite(c);
  EXPECT_GT(finite, c.points.size() / 2);
  EXPECT_LT(finite, c.points.size());
  // Camera frame, y down: the floor (bottom rows) is below the camera (y > 0) and in front (z > 0).
  int floor_like = 0, counted = 0;
  for (std::uint32_t col = 0; col < c.width; col += 8) {
    const Eigen::Vector3f& p = c.at(col, c.height - 20);
    if (!p.allFinite()) continue;
    ++counted;
    floor_like += p.y() > 0.8f && p.z() > 0.5f;
  }
  EXPECT_GT(counted, 20);
  EXPECT_GT(floor_like, counted * 8 / 10);
}

TEST(PcdCloud, UnorganizedAsciiCloud) {
  NAVAID_REQUIRE_SHARED_DATA();
  const PcdCloud c = read_pcd_cloud(pcd_fixture("sac_plane_test.pcd"));
  EXPECT_EQ(c.points.size(), 3283u);
  EXPECT_EQ(c.height, 1u);
  EXPECT_FALSE(c.organized());
  EXPECT_EQ(count_finite(c), c.points.size());
}

TEST(PcdCloud, CloudWithoutCoordinatesIsAnIoError) {
  NAVAID_REQUIRE_SHARED_DATA();
  expect_io_error_naming(pcd_fixture("stereo_left.pcd"));  // rgba only
}

TEST(PcdCloud, MissingTruncatedAndGarbageFilesAreIoErrors) {
  testing::ScratchDir dir("pcd_cloud_corrupt");
  expect_io_error_naming(dir / "missing.pcd");

  testing::write_text(dir / "garbage.pcd", "this is not a point cloud\n\x01\x02\x03 at all\n");
  expect_io_error_naming(dir / "garbage.pcd");

  testing::write_text(dir / "empty.pcd", "");
  expect_io_error_naming(dir / "empty.pcd");

  // An ascii header that promises more points than the file holds.
  testing::write_text(dir / "short.pcd",
                      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 10\nHEIGHT 1\n"
                      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 10\nDATA ascii\n1 2 3\n4 5 6\n");
  expect_io_error_naming(dir / "short.pcd");

  if (!testing::have_shared_data()) return;
  // The first half of a real binary_compressed cloud.
  const std::string bytes = testing::read_text(pcd_fixture("five_people.pcd"));
  ASSERT_GT(bytes.size(), 1000u);
  testing::write_text(dir / "truncated.pcd", bytes.substr(0, bytes.size() / 2));
  expect_io_error_naming(dir / "truncated.pcd");
}

}  // namespace
}  // namespace navaid::mapping
