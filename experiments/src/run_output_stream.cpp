#include "navaid/experiments/run_output_stream.hpp"

#include <fmt/format.h>

#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/core/geometry.hpp"

namespace navaid::experiments {

namespace {

std::ofstream open_for_writing(const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(file.string(), "cannot write");
  return out;
}

double frontend_ms(const runtime::FrameRecord& r) { return r.frontend ? r.frontend->track_ms + r.frontend->load_ms : 0.0; }

std::string estimate_row(const StateEstimate& s) {
  const auto& P = s.covariance;
  std::string row = fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", s.t, s.T_W_B.t.x(),
                                s.T_W_B.t.y(), s.T_W_B.t.z(), s.T_W_B.q.w(), s.T_W_B.q.x(), s.T_W_B.q.y(),
                                s.T_W_B.q.z(), s.v_W.x(), s.v_W.y(), s.v_W.z(), s.b_g.x(), s.b_g.y(), s.b_g.z(),
                                s.b_a.x(), s.b_a.y(), s.b_a.z(), to_string(s.mode));
  for (int base : {3, 0})  // position block, then rotation block (StateEstimate order: rotation first)
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) row += fmt::format(",{}", P(base + i, base + j));
  if (s.T_ENU_W)
    row += fmt::format(",{},{},{},{}", yaw_of(s.T_ENU_W->q), s.T_ENU_W->t.x(), s.T_ENU_W->t.y(), s.T_ENU_W->t.z());
  else
    row += ",,,,";
  return row;
}

std::string timing_row(const runtime::FrameRecord& r, bool realtime) {
  std::string row = fmt::format("{},{:.4f},{}", r.estimate.t, r.ms, to_string(r.estimate.mode));
  row += r.frontend ? fmt::format(",{:.4f},{:.4f}", r.frontend->track_ms, r.frontend->load_ms) : std::string(",,");
  if (realtime) {
    row += r.estimator_ms ? fmt::format(",{:.4f}", *r.estimator_ms) : std::string(",");
    row += r.latency_ms ? fmt::format(",{:.4f}", *r.latency_ms) : std::string(",");
  }
  row += fmt::format(",{:d},{:.4f},{:.4f},{:.4f}", r.stages.keyframe ? 1 : 0, r.stages.solve_ms, r.stages.covariance_ms,
                     r.stages.marginalization_ms);
  return row;
}

}  // namespace

double estimator_ms_of(const runtime::FrameRecord& r) { return r.estimator_ms ? *r.estimator_ms : r.ms - frontend_ms(r); }

RunOutputStream::RunOutputStream(const std::filesystem::path& run_dir, bool realtime)
    : estimates_path_(run_dir / "estimates.csv"),
      timing_path_(run_dir / "timing.csv"),
      estimates_csv_(open_for_writing(estimates_path_)),
      timing_csv_(open_for_writing(timing_path_)),
      trajectory_(run_dir / "trajectory.tum"),
      realtime_(realtime) {
  estimates_csv_ << "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode,"
                    "cov_pxx,cov_pxy,cov_pxz,cov_pyy,cov_pyz,cov_pzz,cov_rxx,cov_rxy,cov_rxz,cov_ryy,cov_ryz,cov_rzz,"
                    "enu_yaw,enu_x,enu_y,enu_z\n";
  // frontend_ms and image_load_ms stay empty for feature-level input; --realtime adds the
  // estimator thread's share and the latency from the frame's arrival to its estimate; the
  // estimator's stages come last (docs/estimator.md, "navaid run").
  timing_csv_ << "t_ns,ms,mode,frontend_ms,image_load_ms" << (realtime ? ",estimator_ms,latency_ms" : "")
              << ",keyframe,solve_ms,covariance_ms,marginalization_ms\n";
}

void RunOutputStream::add(const runtime::FrameRecord& r) {
  const StateEstimate& e = r.estimate;
  estimates_csv_ << estimate_row(e) << '\n';
  timing_csv_ << timing_row(r, realtime_) << '\n';
  if (e.mode != EstimatorMode::kInitializing) trajectory_.add({e.t, e.T_W_B});
  if (!estimates_csv_) throw IoError(estimates_path_.string(), "write failed");
  if (!timing_csv_) throw IoError(timing_path_.string(), "write failed");
  estimates_.push_back(evaluation::run_estimate(e));
  timings_.push_back({e.t, r.ms, estimator_ms_of(r), r.frontend});
}

void RunOutputStream::flush() {
  estimates_csv_.flush();
  timing_csv_.flush();
}

void RunOutputStream::close() {
  estimates_csv_.close();
  if (!estimates_csv_) throw IoError(estimates_path_.string(), "write failed");
  timing_csv_.close();
  if (!timing_csv_) throw IoError(timing_path_.string(), "write failed");
  trajectory_.close();
}

}  // namespace navaid::experiments
