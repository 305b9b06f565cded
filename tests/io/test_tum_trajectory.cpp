#include <gtest/gtest.h>

#include <set>

#include "fixtures/fixture_util.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::read_text;
using testing::write_text;
using testing::datasets::expect_io_error;

struct RealFile {
  const char* path;  // under rpg-euroc-V1_02/
  std::size_t poses;
  Timestamp first, last;
};

// Counted with awk (non-comment lines) and read off head/tail; stamps rounded to the nanosecond
// (e.g. "1403715608.1121430397" -> ...112143040, "1.403715524907143116e+09" -> ...907143116).
constexpr RealFile kRealFiles[] = {
    {"vislam_ba/stamped_ba_estimate0.txt", 264, 1403715529262140000LL, 1403715600662140000LL},
    {"vislam_ba/stamped_ba_estimate1.txt", 269, 1403715529262140000LL, 1403715600812140000LL},
    {"vislam_ba/stamped_ba_estimate2.txt", 265, 1403715529262140000LL, 1403715600812140000LL},
    {"vislam_ba/stamped_ba_estimate3.txt", 269, 1403715529262140000LL, 1403715600862140000LL},
    {"vislam_ba/stamped_ba_estimate4.txt", 268, 1403715529262140000LL, 1403715600812140000LL},
    {"vislam_ba/stamped_ba_estimate5.txt", 277, 1403715529262140000LL, 1403715600862140000LL},
    {"vislam_ba/stamped_ba_estimate6.txt", 268, 1403715529262140000LL, 1403715600662140000LL},
    {"vislam_ba/stamped_ba_estimate7.txt", 271, 1403715529262140000LL, 1403715600662140000LL},
    {"vislam_ba/stamped_ba_estimate8.txt", 270, 1403715529262140000LL, 1403715600862140000LL},
    {"vislam_ba/stamped_ba_estimate9.txt", 268, 1403715529262140000LL, 1403715601062140000LL},
    {"vislam_ba/stamped_groundtruth.txt", 16702, 1403715524907143116LL, 1403715608412142992LL},
    {"vislam_rp/stamped_groundtruth.txt", 16702, 1403715524907143116LL, 1403715608412142992LL},
    {"vislam_rp/stamped_traj_estimate0.txt", 1355, 1403715540412142992LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate1.txt", 1367, 1403715539812143087LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate2.txt", 1361, 1403715540112143040LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate3.txt", 1397, 1403715538312143087LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate4.txt", 1366, 1403715539862143040LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate5.txt", 1452, 1403715535562143087LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate6.txt", 1366, 1403715539862143040LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate7.txt", 1437, 1403715536312143087LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate8.txt", 1417, 1403715537312143087LL, 1403715608112143040LL},
    {"vislam_rp/stamped_traj_estimate9.txt", 1360, 1403715540162142992LL, 1403715608112143040LL},
};

fs::path real_dir() { return testing::shared_data_dir() / "rpg-euroc-V1_02"; }

TEST(TumTrajectoryRealData, EveryTrajectoryFileIsCovered) {
  NAVAID_REQUIRE_SHARED_DATA();
  std::set<std::string> listed;
  for (const auto& f : kRealFiles) listed.insert(f.path);
  for (const auto& entry : fs::recursive_directory_iterator(real_dir())) {
    if (!entry.is_regular_file()) continue;
    const std::string rel = fs::relative(entry.path(), real_dir()).generic_string();
    const std::string name = entry.path().filename().string();
    // SOURCE.md describes the data; eval_cfg.yaml is rpg_trajectory_evaluation's alignment setting.
    if (name == "SOURCE.md" || name == "eval_cfg.yaml") continue;
    EXPECT_EQ(listed.count(rel), 1u) << rel << " is not checked by this test";
  }
}

TEST(TumTrajectoryRealData, CountsAndFirstLastStamps) {
  NAVAID_REQUIRE_SHARED_DATA();
  for (const auto& f : kRealFiles) {
    SCOPED_TRACE(f.path);
    const auto poses = read_tum_trajectory(real_dir() / f.path);
    ASSERT_EQ(poses.size(), f.poses);
    EXPECT_EQ(poses.front().t, f.first);
    EXPECT_EQ(poses.back().t, f.last);
    for (const auto& p : poses) ASSERT_NEAR(p.T_W_B.q.norm(), 1.0, 1e-14);
  }
}

TEST(TumTrajectoryRealData, GroundTruthFirstPoseValues) {
  NAVAID_REQUIRE_SHARED_DATA();
  // head -2 vislam_rp/stamped_groundtruth.txt
  const auto poses = read_tum_trajectory(real_dir() / "vislam_rp/stamped_groundtruth.txt");
  const auto& p = poses.front();
  EXPECT_EQ(format_seconds(p.t), "1403715524.907143116");
  EXPECT_DOUBLE_EQ(p.T_W_B.t.x(), 5.153560000000000363e-01);
  EXPECT_DOUBLE_EQ(p.T_W_B.t.y(), 1.996772999999999909e+00);
  EXPECT_DOUBLE_EQ(p.T_W_B.t.z(), 9.711039999999999672e-01);
  // qx qy qz qw in the file; the stored quaternion is the normalized one (|q| - 1 ~ 1e-6 here).
  const Quat q(1.619960000000000011e-01, 7.899850000000000483e-01, -2.053760000000000030e-01,
               5.545280000000000209e-01);
  EXPECT_LT(p.T_W_B.q.angularDistance(q.normalized()), 1e-12);
  EXPECT_NEAR(p.T_W_B.q.w(), q.normalized().w(), 1e-12);
  // Both folders hold the same ground truth.
  const auto other = read_tum_trajectory(real_dir() / "vislam_ba/stamped_groundtruth.txt");
  ASSERT_EQ(other.size(), poses.size());
  EXPECT_EQ(other.back().t, poses.back().t);
}

TEST(TumTrajectoryRealData, WriteReadWriteIsByteIdenticalAndLossless) {
  NAVAID_REQUIRE_SHARED_DATA();
  ScratchDir dir("tum-traj-roundtrip");
  for (const auto& f : kRealFiles) {
    SCOPED_TRACE(f.path);
    const auto poses = read_tum_trajectory(real_dir() / f.path);
    write_tum_trajectory(dir / "a.txt", poses);
    const auto again = read_tum_trajectory(dir / "a.txt");
    ASSERT_EQ(again.size(), poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
      ASSERT_EQ(again[i].t, poses[i].t);
      ASSERT_EQ(again[i].T_W_B.t, poses[i].T_W_B.t);
      ASSERT_EQ(again[i].T_W_B.q.coeffs(), poses[i].T_W_B.q.coeffs());
    }
    write_tum_trajectory(dir / "b.txt", again);
    ASSERT_EQ(read_text(dir / "a.txt"), read_text(dir / "b.txt"));
  }
}

TEST(TumTrajectoryRealData, RecordingVariant) {
  NAVAID_REQUIRE_SHARED_DATA();
  const auto rec = read_tum_trajectory_recording(real_dir() / "vislam_rp/stamped_traj_estimate0.txt");
  EXPECT_EQ(rec.format, "tum-trajectory");
  EXPECT_EQ(rec.groundtruth.size(), 1355u);
  EXPECT_TRUE(rec.imu.empty());
  EXPECT_TRUE(rec.frames.empty());
  EXPECT_EQ(rec.report.total(), 0u);
  EXPECT_EQ(rec.groundtruth.front().t, 1403715540412142992LL);
  EXPECT_FALSE(rec.groundtruth.front().v_W.has_value());
}

TEST(TumTrajectory, WriterFormat) {
  ScratchDir dir("tum-traj-format");
  StampedPose p;
  p.t = 1403715524907143116LL;
  p.T_W_B = SE3(Quat(0.5, 0.5, -0.5, 0.5), Vec3(0.515356, -2.0, 1e-7));
  write_tum_trajectory(dir / "t.txt", {p});
  EXPECT_EQ(read_text(dir / "t.txt"),
            "# timestamp tx ty tz qx qy qz qw\n"
            "1403715524.907143116 0.515356 -2 1e-07 0.5 -0.5 0.5 0.5\n");
  EXPECT_EQ(format_tum_pose(p), "1403715524.907143116 0.515356 -2 1e-07 0.5 -0.5 0.5 0.5");
}

TEST(TumTrajectory, AcceptsCommentsBlankLinesTabsScientificAndCrlf) {
  ScratchDir dir("tum-traj-variants");
  write_text(dir / "t.txt",
             "# written by hand\r\n"
             "\r\n"
             "1.305031098665900e+09\t1.3563 0.6305  1.6380 0.6132 0.5962 -0.3311 -0.3986\r\n"
             "   # indented comment\r\n"
             "1305031098.6758 1.3543 6.306e-01 1.6360 0.6129 0.5966 -0.3316 -0.3980\r\n");
  const auto poses = read_tum_trajectory(dir / "t.txt");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].t, 1305031098665900000LL);
  EXPECT_EQ(poses[1].t, 1305031098675800000LL);
  EXPECT_DOUBLE_EQ(poses[1].T_W_B.t.y(), 0.6306);
  EXPECT_NEAR(poses[0].T_W_B.q.norm(), 1.0, 1e-15);
  EXPECT_LT(poses[0].T_W_B.q.angularDistance(Quat(-0.3986, 0.6132, 0.5962, -0.3311).normalized()), 1e-12);
}

TEST(TumTrajectory, EmptyFileGivesNoPoses) {
  ScratchDir dir("tum-traj-empty");
  write_text(dir / "t.txt", "# timestamp tx ty tz qx qy qz qw\n");
  EXPECT_TRUE(read_tum_trajectory(dir / "t.txt").empty());
}

class TumTrajectoryCorrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    write_text(file_,
               "# timestamp tx ty tz qx qy qz qw\n"
               "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"
               "1305031098.6758 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980\n"
               "1305031098.6858 1.3524 0.6304 1.6345 0.6132 0.5976 -0.3313 -0.3970\n");
  }
  void expect_line3_error(const std::string& line3, std::initializer_list<std::string> fragments) {
    testing::datasets::replace_line(file_, 3, line3);
    expect_io_error([&] { read_tum_trajectory(file_); }, "t.txt", 3, fragments);
  }
  ScratchDir dir_{"tum-traj-corrupt"};
  fs::path file_ = dir_ / "t.txt";
};

TEST_F(TumTrajectoryCorrupt, FixtureIsValid) { EXPECT_EQ(read_tum_trajectory(file_).size(), 3u); }

TEST_F(TumTrajectoryCorrupt, TruncatedLine) {
  expect_line3_error("1305031098.6758 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316", {"expected 8 fields, found 7"});
}

TEST_F(TumTrajectoryCorrupt, NonNumericField) {
  expect_line3_error("1305031098.6758 1.3543 x0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980",
                     {"column 'ty'", "'x0.6306' is not a number"});
}

TEST_F(TumTrajectoryCorrupt, NanAndInf) {
  expect_line3_error("1305031098.6758 nan 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980",
                     {"column 'tx'", "not a finite number"});
  expect_line3_error("1305031098.6758 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 inf",
                     {"column 'qw'", "not a finite number"});
}

TEST_F(TumTrajectoryCorrupt, BadTimestamp) {
  expect_line3_error("1305031098.67x8 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980",
                     {"column 'timestamp'", "not a time in seconds"});
}

TEST_F(TumTrajectoryCorrupt, DuplicateAndDecreasingTimestamps) {
  expect_line3_error("1305031098.6659 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980",
                     {"duplicate timestamp 1305031098.665900000"});
  expect_line3_error("1305031098.6000 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980",
                     {"decreasing timestamp 1305031098.600000000"});
}

TEST_F(TumTrajectoryCorrupt, QuaternionNotUnit) {
  expect_line3_error("1305031098.6758 1.3543 0.6306 1.6360 0.6190 0.5966 -0.3316 -0.3980",
                     {"quaternion", "not within 1e-3 of 1"});
  expect_line3_error("1305031098.6758 1.3543 0.6306 1.6360 0 0 0 0", {"has norm 0"});
}

TEST_F(TumTrajectoryCorrupt, MissingFile) {
  expect_io_error([&] { read_tum_trajectory(dir_ / "absent.txt"); }, "absent.txt", 0, {"does not exist"});
}

TEST(TumTrajectory, WriterRejectsBadInput) {
  ScratchDir dir("tum-traj-writer");
  StampedPose a, b;
  a.t = 2;
  b.t = 1;
  expect_io_error([&] { write_tum_trajectory(dir / "t.txt", {a, b}); }, "t.txt", 0, {"pose 1", "not after"});
  b.t = 3;
  b.T_W_B.t.x() = std::numeric_limits<double>::quiet_NaN();
  expect_io_error([&] { write_tum_trajectory(dir / "t.txt", {a, b}); }, "t.txt", 0, {"pose 1", "non-finite"});
  expect_io_error([&] { write_tum_trajectory(dir / "missing-dir" / "t.txt", {a}); }, "t.txt", 0,
                  {"cannot open for writing"});
}

TEST(TumTrajectory, StreamingWriterWritesTheSameBytesAndChecksEachPose) {
  NAVAID_REQUIRE_SHARED_DATA();
  ScratchDir dir("tum-traj-stream");
  const auto poses = read_tum_trajectory(real_dir() / "vislam_rp/stamped_traj_estimate0.txt");
  write_tum_trajectory(dir / "whole.txt", poses);
  {
    TumTrajectoryWriter writer(dir / "streamed.txt");
    for (const auto& p : poses) writer.add(p);
    EXPECT_EQ(writer.poses(), poses.size());
    writer.close();
  }
  EXPECT_EQ(read_text(dir / "whole.txt"), read_text(dir / "streamed.txt"));

  TumTrajectoryWriter writer(dir / "bad.txt");
  writer.add(poses[1]);
  expect_io_error([&] { writer.add(poses[0]); }, "bad.txt", 0, {"pose 1", "not after"});
  StampedPose nan = poses[2];
  nan.T_W_B.q.w() = std::numeric_limits<double>::infinity();
  expect_io_error([&] { writer.add(nan); }, "bad.txt", 0, {"pose 1", "non-finite"});
  writer.add(poses[2]);  // a rejected pose is not written: the file stays a valid trajectory
  writer.close();
  EXPECT_EQ(read_tum_trajectory(dir / "bad.txt").size(), 2u);
  expect_io_error([&] { TumTrajectoryWriter(dir / "missing-dir" / "t.txt"); }, "t.txt", 0, {"cannot open for writing"});
}

}  // namespace
}  // namespace navaid::io
