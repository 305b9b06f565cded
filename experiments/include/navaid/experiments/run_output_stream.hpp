#pragma once
// navaid run's per-frame files, written as the run goes (docs/estimator.md, "navaid run"):
// estimates.csv (every estimate with its covariance blocks), trajectory.tum (the estimates past
// initialization) and timing.csv (each frame's cost). Of every frame the run then keeps only a
// RunEstimate and a FrameTiming (~330 B) for its summary, so its memory does not grow with the
// length of the walk, and a run that fails part-way leaves its files up to the failure.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/evaluation/run_estimate.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::experiments {

/// What a frame cost, as the summary and stages.csv need it.
struct FrameTiming {
  Timestamp t = 0;
  double ms = 0;            ///< runtime::FrameRecord::ms
  double estimator_ms = 0;  ///< the estimator's share (replay: ms less loading and tracking)
  std::optional<runtime::FrontendTime> frontend;
};

/// The estimator's half of a record's cost: real time, the estimator thread's share; replay, what
/// the frame cost beyond loading and tracking its images.
double estimator_ms_of(const runtime::FrameRecord& r);

class RunOutputStream {
 public:
  /// Creates the three files in `run_dir` (which must exist); `realtime` adds timing.csv's
  /// estimator_ms and latency_ms columns. IoError when a file cannot be written.
  RunOutputStream(const std::filesystem::path& run_dir, bool realtime);

  /// Writes the record's rows and keeps its compact part. IoError on a write failure or a
  /// trajectory pose that is not finite or not after the previous one.
  void add(const runtime::FrameRecord& r);
  /// Flushes and closes the files; IoError when a write failed. Called once, at the run's end.
  void close();
  /// Flushes what was written so far without judging it (a failing run keeps its rows).
  void flush();

  const std::vector<evaluation::RunEstimate>& estimates() const { return estimates_; }
  const std::vector<FrameTiming>& timings() const { return timings_; }

 private:
  std::filesystem::path estimates_path_, timing_path_;
  std::ofstream estimates_csv_, timing_csv_;
  io::TumTrajectoryWriter trajectory_;
  bool realtime_;
  std::vector<evaluation::RunEstimate> estimates_;
  std::vector<FrameTiming> timings_;
};

}  // namespace navaid::experiments
