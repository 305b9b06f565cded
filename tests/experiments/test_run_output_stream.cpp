// RunOutputStream: navaid run's per-frame files written as the estimates come, and the compact
// record the run keeps of each frame (what bounds an hour-long walk's memory).
#include "navaid/experiments/run_output_stream.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/evaluation/start_alignment.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::experiments {
namespace {

using navaid::testing::read_text;
using navaid::testing::ScratchDir;

runtime::FrameRecord record(int k, EstimatorMode mode) {
  runtime::FrameRecord r;
  r.estimate.t = seconds_to_ns(0.1 * k);
  r.estimate.mode = mode;
  r.estimate.T_W_B = SE3(quat_from_rpy(0.01 * k, -0.02 * k, 0.3 * k), Vec3(0.5 * k, -0.25 * k, 1.0 + 0.01 * k));
  r.estimate.v_W = Vec3(1.0, 0.5 * k, -0.1);
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) r.estimate.covariance(i, j) = i == j ? 1e-3 * (i + 1 + k) : 1e-5 * (i + j);
  if (k >= 2) r.estimate.T_ENU_W = SE3(quat_from_rpy(0, 0, 0.7), Vec3(3, 4, 5));
  r.ms = 10.0 + k;
  r.stages.solve_ms = 4.0 + k;
  if (k % 2 == 1) r.frontend = runtime::FrontendTime{2.0, 1.5};
  return r;
}

std::size_t lines(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

TEST(RunOutputStream, WritesEveryRecordAsItComesAndKeepsItsCompactPart) {
  ScratchDir dir("run-output-stream");
  const std::vector<runtime::FrameRecord> records{record(0, EstimatorMode::kInitializing), record(1, EstimatorMode::kVio),
                                         record(2, EstimatorMode::kRgbdVio), record(3, EstimatorMode::kImuOnly)};
  RunOutputStream stream(dir.path(), false);
  for (const auto& r : records) stream.add(r);
  stream.flush();
  // Each row is on disk before the run ends (a run that fails part-way keeps them).
  EXPECT_EQ(lines(read_text(dir / "estimates.csv")), 1 + records.size());
  stream.close();

  const std::vector<StateEstimate> back = read_estimates_csv(dir / "estimates.csv");
  ASSERT_EQ(back.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const StateEstimate& e = records[i].estimate;
    EXPECT_EQ(back[i].t, e.t);
    EXPECT_EQ(back[i].mode, e.mode);
    EXPECT_TRUE(back[i].T_W_B.is_approx(e.T_W_B, 1e-12));
    const Mat3 rotation = e.covariance.block<3, 3>(0, 0), position = e.covariance.block<3, 3>(3, 3);
    EXPECT_TRUE((back[i].covariance.block<3, 3>(0, 0).isApprox(rotation, 1e-12)));
    EXPECT_TRUE((back[i].covariance.block<3, 3>(3, 3).isApprox(position, 1e-12)));
  }
  // trajectory.tum: the estimates past initialization, as write_tum_trajectory writes them.
  const auto traj = io::read_tum_trajectory(dir / "trajectory.tum");
  ASSERT_EQ(traj.size(), 3u);
  EXPECT_EQ(traj.front().t, records[1].estimate.t);
  // timing.csv: one row per record; the front end's columns only where it ran.
  std::istringstream timing(read_text(dir / "timing.csv"));
  std::string header, row;
  std::getline(timing, header);
  EXPECT_EQ(header, "t_ns,ms,mode,frontend_ms,image_load_ms,keyframe,solve_ms,covariance_ms,marginalization_ms");
  std::getline(timing, row);
  EXPECT_EQ(row, std::to_string(records[0].estimate.t) + ",10.0000,initializing,,,0,4.0000,0.0000,0.0000");
  std::getline(timing, row);
  EXPECT_EQ(row, std::to_string(records[1].estimate.t) + ",11.0000,vio,2.0000,1.5000,0,5.0000,0.0000,0.0000");

  // The compact part: what the summary needs, equal to what the full estimates give.
  ASSERT_EQ(stream.estimates().size(), records.size());
  ASSERT_EQ(stream.timings().size(), records.size());
  EXPECT_DOUBLE_EQ(stream.timings()[1].estimator_ms, 11.0 - 3.5);  // replay: the frame less loading and tracking
  EXPECT_DOUBLE_EQ(stream.timings()[2].estimator_ms, 12.0);
  EXPECT_FALSE(stream.estimates()[1].T_ENU_W.has_value());
  ASSERT_TRUE(stream.estimates()[2].T_ENU_W.has_value());
  std::vector<StateEstimate> full;
  std::vector<io::StampedPose> gt;
  for (const auto& r : records) {
    full.push_back(r.estimate);
    gt.push_back({r.estimate.t, SE3(quat_from_rpy(0, 0, 0.1), Vec3(1, 1, 1)) * r.estimate.T_W_B});
  }
  const auto from_full = evaluation::align_to_first_state(full, gt);
  const auto from_compact = evaluation::align_to_first_state(stream.estimates(), gt);
  ASSERT_EQ(from_full.size(), 3u);
  ASSERT_EQ(from_compact.size(), from_full.size());
  for (std::size_t i = 0; i < from_full.size(); ++i) {
    EXPECT_EQ(from_compact[i].t, from_full[i].t);
    EXPECT_TRUE(from_compact[i].T_W_B.is_approx(from_full[i].T_W_B, 0.0));
    EXPECT_EQ(from_compact[i].position_covariance, from_full[i].position_covariance);
    EXPECT_EQ(from_compact[i].rotation_covariance, from_full[i].rotation_covariance);
  }
}

TEST(RunOutputStream, RealTimeAddsItsColumnsAndABadPoseIsAClearError) {
  ScratchDir dir("run-output-stream-rt");
  RunOutputStream stream(dir.path(), true);
  runtime::FrameRecord r = record(1, EstimatorMode::kVio);
  r.estimator_ms = 6.0;
  r.latency_ms = 20.0;
  stream.add(r);
  EXPECT_DOUBLE_EQ(stream.timings()[0].estimator_ms, 6.0);  // real time: the estimator thread's share
  runtime::FrameRecord earlier = record(0, EstimatorMode::kVio);
  try {
    stream.add(earlier);
    FAIL() << "a pose before the previous one was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.tum"), std::string::npos) << e.what();
  }
  stream.close();
  std::istringstream timing(read_text(dir / "timing.csv"));
  std::string header, row;
  std::getline(timing, header);
  EXPECT_EQ(header,
            "t_ns,ms,mode,frontend_ms,image_load_ms,estimator_ms,latency_ms,keyframe,solve_ms,covariance_ms,"
            "marginalization_ms");
  EXPECT_THROW(RunOutputStream(dir / "no-such-folder", false), IoError);
}

}  // namespace
}  // namespace navaid::experiments
