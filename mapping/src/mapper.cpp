#include "navaid/mapping/mapper.hpp"

#include <chrono>

namespace navaid::mapping {

MapperConfig read_mapper_config(const Config& c) {
  MapperConfig m;
  m.cloud = read_semantic_point_cloud_config(c);
  m.map = read_semantic_map_config(c);
  m.gate = read_mapping_gate_config(c);
  return m;
}

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Mapper::Mapper(const MapperConfig& config, const CameraCalibration& camera)
    : config_(config), camera_(camera), map_(config.map) {}

MapperFrameResult Mapper::process(const RgbdFrame& frame, const StateEstimate& estimate) {
  MapperFrameResult r;
  ++counters_.frames;
  r.uncertainty = pose_uncertainty(estimate);
  last_uncertainty_ = r.uncertainty;
  switch (gate(estimate, r.uncertainty, config_.gate)) {
    case GateDecision::kSkipMode:
      r.outcome = FrameOutcome::kNotLocalised;
      ++counters_.not_localised;
      return r;
    case GateDecision::kSkipUncertain:
      r.outcome = FrameOutcome::kTooUncertain;
      ++counters_.too_uncertain;
      return r;
    case GateDecision::kMap:
      break;
  }
  if (frame.depth.empty()) {
    r.outcome = FrameOutcome::kNoDepth;
    ++counters_.no_depth;
    return r;
  }
  auto t0 = std::chrono::steady_clock::now();
  const SemanticPointCloud cloud = make_semantic_point_cloud(frame, camera_, estimate.T_W_B, config_.cloud);
  r.cloud_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  map_.set_window_center(estimate.T_W_B.t);
  r.insert = map_.insert(cloud);
  r.insert_ms = ms_since(t0);
  r.points = cloud.points.size();
  counters_.points += r.points;
  ++counters_.mapped;
  return r;
}

}  // namespace navaid::mapping
