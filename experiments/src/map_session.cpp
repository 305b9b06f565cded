#include "navaid/experiments/map_session.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/start_alignment.hpp"
#include "navaid/mapping/map_png.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"

namespace navaid::experiments {

namespace {

/// The top view shows what lies below 0.3 m over the body (the IMU: head, cane or hand height).
constexpr double kTopViewAboveBodyM = 0.3;

/// Resident memory of this process now and at its peak [MiB] (Linux /proc).
std::pair<double, double> rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string key;
  double now = 0, peak = 0;
  while (status >> key) {
    double kib = 0;
    if (key == "VmRSS:" && status >> kib) now = kib / 1024.0;
    else if (key == "VmHWM:" && status >> kib) peak = kib / 1024.0;
  }
  return {now, peak};
}

std::string outcome_name(mapping::FrameOutcome o) {
  switch (o) {
    case mapping::FrameOutcome::kMapped: return "mapped";
    case mapping::FrameOutcome::kNoDepth: return "no-depth";
    case mapping::FrameOutcome::kNotLocalised: return "not-localised";
    case mapping::FrameOutcome::kTooUncertain: return "too-uncertain";
  }
  return "?";
}


nlohmann::ordered_json quality_json(const evaluation::MapQuality& q, const simulation::Scenario& scenario) {
  nlohmann::ordered_json j;
  j["occupancy"] = {{"precision", q.precision}, {"recall", q.recall}, {"f1", q.f1}, {"true_positive", q.true_positive},
                    {"false_positive", q.false_positive}, {"false_negative", q.false_negative}};
  j["semantic_accuracy"] = q.semantic_accuracy;
  nlohmann::ordered_json classes = nlohmann::ordered_json::object();
  for (const auto& [c, acc] : q.per_class)
    classes[std::string(semantic_class_name(c))] = {
        {"accuracy", acc.total ? static_cast<double>(acc.correct) / static_cast<double>(acc.total) : 0.0},
        {"voxels", acc.total}};
  j["semantic_accuracy_per_class"] = classes;
  nlohmann::ordered_json obstacles = nlohmann::ordered_json::array();
  for (const auto& d : q.deliberate)
    obstacles.push_back({{"primitive", d.primitive}, {"on_path", d.on_path}, {"class", std::string(semantic_class_name(d.semantic))},
                         {"z_min_above_ground_m", d.min_z_m - scenario.ground_z_m},
                         {"z_max_above_ground_m", d.max_z_m - scenario.ground_z_m}, {"in_reach", d.in_reach},
                         {"detected", d.detected}});
  j["obstacles"] = obstacles;
  j["obstacles_in_reach"] = q.in_reach;
  j["obstacles_detected"] = q.detected;
  j["obstacle_recall"] = q.deliberate_recall;
  j["on_path_obstacles_in_reach"] = q.on_path_in_reach;
  j["on_path_obstacles_detected"] = q.on_path_detected;
  j["on_path_obstacle_recall"] = q.on_path_recall;
  j["snapshots"] = q.snapshots;
  return j;
}

}  // namespace

std::optional<simulation::Scenario> recording_scenario(const std::filesystem::path& recording) {
  const auto file = recording / "simulation.yaml";
  if (!std::filesystem::is_regular_file(file)) return std::nullopt;
  const Config c = Config::load(file);
  return simulation::make_scenario(simulation::read_scenario_name(c), simulation::read_scenario_options(c));
}

std::vector<io::StampedPose> groundtruth_poses(const io::Recording& recording) {
  std::vector<io::StampedPose> gt;
  gt.reserve(recording.groundtruth.size());
  for (const auto& g : recording.groundtruth) gt.push_back({g.t, g.T_W_B});
  return gt;
}

Timestamp recording_start(const io::Recording& recording) {
  std::optional<Timestamp> start;
  const auto earliest = [&start](Timestamp t) { start = start ? std::min(*start, t) : t; };
  if (!recording.imu.empty()) earliest(recording.imu.front().t);
  if (!recording.frames.empty()) earliest(recording.frames.front().t);
  if (!recording.gps.empty()) earliest(recording.gps.front().t);
  if (!recording.mag.empty()) earliest(recording.mag.front().t);
  return start.value_or(0);
}

MapSession::MapSession(const runtime::MappingStage& stage, const std::filesystem::path& recording_dir,
                       const std::filesystem::path& out, const MapSessionOptions& options)
    : stage_(stage),
      out_(out),
      options_(options),
      top_view_(stage.config().map.resolution_m),
      scenario_(options.quality ? recording_scenario(recording_dir) : std::nullopt) {
  if (!(options.snapshot_every_s > 0)) throw UsageError("the map snapshot interval must be positive");
  const double resolution_m = stage.config().map.resolution_m;
  if (scenario_) {
    quality_ = std::make_unique<evaluation::MapQualityAccumulator>(*scenario_, resolution_m);
    if (!options.align_to.empty())
      quality_global_ = std::make_unique<evaluation::MapQualityAccumulator>(*scenario_, resolution_m);
  }
  std::filesystem::create_directories(out_);
  timing_.open(out_ / "timing.csv");
  if (!timing_) throw IoError((out_ / "timing.csv").string(), "cannot write");
  if (const auto& obstacles = stage.options().obstacles) {
    obstacle_csv_.open(out_ / "obstacle_scan.csv");
    if (!obstacle_csv_) throw IoError((out_ / "obstacle_scan.csv").string(), "cannot write");
    const auto& o = *obstacles;
    obstacle_csv_ << "t_ns,ground,ransac,obstacle_points,drop_off_points";
    // Nearest obstacle (r_) and nearest drop-off (d_) per bearing bin.
    for (const char* kind : {"r", "d"})
      for (std::size_t b = 0; b < o.scan_bins(); ++b)
        obstacle_csv_ << fmt::format(",{}_{:.0f}", kind,
                                     (o.scan_min_bearing_rad + static_cast<double>(b) * o.scan_bin_width_rad) * 180.0 / M_PI);
    obstacle_csv_ << "\n";
  }
  if (stage.link()) {
    network_csv_.open(out_ / "network.csv");
    if (!network_csv_) throw IoError((out_ / "network.csv").string(), "cannot write");
    network_csv_ << "t_s,event\n";  // seconds after the recording start, as mapping.network.outages
  }
  timing_ << "t_ns,frame,outcome,sigma_xy_m,sigma_yaw_deg,gated_sigma_xy_m,gated_sigma_yaw_deg,points,occupied_voxels,free_voxels,cloud_ms,insert_ms,"
             "layers_ms,esdf_ms\n";
}

MapSession::~MapSession() = default;

void MapSession::record(const RgbdFrame& frame, const StateEstimate& estimate, const runtime::MappedFrame& mapped) {
  ++frames_seen_;
  for (const auto& c : mapped.network_changes) {
    network_csv_ << fmt::format("{:.3f},{}\n", static_cast<double>(c.t - stage_.options().network_start) * 1e-9,
                                mapping::network_change_name(c.kind));
    network_events_.push_back(runtime::network_event(c));
  }
  const mapping::MapperFrameResult& r = mapped.result;
  if (mapped.scan) write_obstacle_row(*mapped.scan);
  timing_ << fmt::format("{},{},{},{:.4f},{:.3f},{:.4f},{:.3f},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f}\n", frame.t,
                         frame.index, outcome_name(r.outcome), r.uncertainty.sigma_xy,
                         r.uncertainty.sigma_yaw * 180.0 / M_PI, r.gated.sigma_xy, r.gated.sigma_yaw * 180.0 / M_PI,
                         r.points, r.insert.occupied_voxels, r.insert.free_voxels, r.cloud_ms, r.insert_ms, r.layers_ms,
                         r.esdf_ms);
  const mapping::Mapper& mapper = stage_.mapper();
  if (r.outcome == mapping::FrameOutcome::kMapped) {
    if (quality_global_ && !aligned_) {
      quality_global_->set_map_to_truth(evaluation::first_state_transform(estimate, options_.align_to));
      aligned_ = true;
    }
    cloud_ms_.push_back(r.cloud_ms);
    insert_ms_.push_back(r.insert_ms);
    layers_ms_.push_back(r.layers_ms);
    esdf_ms_.push_back(r.esdf_ms);
    total_ms_.push_back(r.cloud_ms + r.insert_ms + r.layers_ms + r.esdf_ms);
    if (options_.png_every_s > 0 && mapper.local_maps() &&
        (!last_png_ || frame.t - *last_png_ >= static_cast<Timestamp>(options_.png_every_s * 1e9))) {
      last_png_ = frame.t;
      write_layer_pngs(out_ / "snapshots", fmt::format("{:04d}-", pngs_++));
    }
    top_view_.add_path_point(estimate.T_W_B.t);
    if (!last_snapshot_ || frame.t - *last_snapshot_ >= static_cast<Timestamp>(options_.snapshot_every_s * 1e9)) {
      last_snapshot_ = frame.t;
      top_view_.add_voxels(mapper.map().occupied_voxels(), estimate.T_W_B.t.z() + kTopViewAboveBodyM);
      if (quality_) {
        if (!options_.align_to.empty())
          quality_->set_map_to_truth(evaluation::first_state_transform(estimate, options_.align_to));
        quality_->add_snapshot(mapper.map(), estimate.T_W_B.t);
      }
      if (quality_global_) quality_global_->add_snapshot(mapper.map(), estimate.T_W_B.t);
    }
  }
  const std::size_t seen = frames_seen_ + no_pose_;
  while (options_.frames_total > 0 && next_quarter_ <= 4 && 4 * seen >= next_quarter_ * options_.frames_total) {
    const auto [now, peak] = rss_mib();
    memory_.push_back({{"route_fraction", 0.25 * static_cast<double>(next_quarter_)}, {"rss_mib", now},
                       {"peak_rss_mib", peak}, {"map_leaves", mapper.map().leaf_count()},
                       {"map_bytes", mapper.map().memory_bytes()}});
    ++next_quarter_;
  }
}

void MapSession::write_obstacle_row(const mapping::ObstacleScan& scan) {
  obstacle_csv_ << fmt::format("{},{},{},{},{}", scan.t, static_cast<int>(scan.counters.ground_source),
                               scan.counters.ransac_succeeded ? 1 : 0, scan.counters.obstacle_points,
                               scan.counters.drop_off_points);
  for (const auto* ranges : {&scan.ranges, &scan.drop_off_ranges})
    for (const float r : *ranges) obstacle_csv_ << "," << (std::isfinite(r) ? fmt::format("{:.3f}", r) : std::string());
  obstacle_csv_ << "\n";
}

void MapSession::write_layer_pngs(const std::filesystem::path& dir, const std::string& prefix) const {
  const mapping::LocalMaps* maps = stage_.mapper().local_maps();
  if (maps == nullptr) return;
  std::filesystem::create_directories(dir);
  mapping::write_height_map_png(dir / (prefix + "height.png"), maps->height);
  mapping::write_undulation_map_png(dir / (prefix + "undulation.png"), maps->undulation);
  mapping::write_collision_map_png(dir / (prefix + "collision.png"), maps->collision);
  mapping::write_cost_map_png(dir / (prefix + "cost.png"), maps->cost);
  mapping::write_esdf_png(dir / (prefix + "esdf.png"), maps->esdf);
}

nlohmann::ordered_json MapSession::finish(const nlohmann::ordered_json& extra) {
  const mapping::Mapper& mapper = stage_.mapper();
  const mapping::MapperConfig& config = stage_.config();
  const auto& n = mapper.counters();
  if (n.no_depth > 0) spdlog::warn("{} frames without depth were not mapped", n.no_depth);
  // A device that maps no frame by design (map_every 0) is not warned about.
  if (n.mapped == 0 && n.frames > 0) spdlog::warn("no frame was mapped (timing.csv's outcome column says why)");
  const mapping::SemanticMap& map = mapper.map();
  map.save(out_ / "map.ot");
  map.write_color_octree(out_ / "map-color.ot");
  map.write_ply(out_ / "map.ply");
  top_view_.add_voxels(map.occupied_voxels(), map.window_center().z() + kTopViewAboveBodyM);
  if (top_view_.painted_cells() > 0) top_view_.write_png(out_ / "topview.png");
  write_layer_pngs(out_, "");

  const auto voxels = map.occupied_voxels();
  const auto labelled = static_cast<std::size_t>(std::count_if(voxels.begin(), voxels.end(), [](const mapping::MapVoxel& v) {
    return v.semantic != SemanticClass::kUnlabeled;
  }));
  nlohmann::ordered_json j = extra;
  j["frames"] = {{"total", frames_seen_ + no_pose_}, {"without_pose", no_pose_}, {"mapped", n.mapped},
                 {"no_depth", n.no_depth}, {"not_localised", n.not_localised}, {"too_uncertain", n.too_uncertain}};
  j["points_inserted"] = n.points;
  j["map"] = {{"resolution_m", config.map.resolution_m},
              {"fusion", config.map.fusion == mapping::FusionPolicy::kMax ? "max" : "bayes"},
              {"window_size_m", config.map.window_size_m},
              {"leaves", map.leaf_count()},
              {"bytes", map.memory_bytes()},
              {"occupied_voxels_in_window", voxels.size()},
              {"labelled_voxels_in_window", labelled}};
  if (const mapping::SegmentationLink* link = stage_.link()) {
    const mapping::SegmentationLinkConfig& network = *stage_.options().network;
    network_csv_.flush();
    interaction::write_guidance_timeline_csv(out_ / "system_events.csv", network_events_);
    j["network"] = {{"outages_configured", network.outages.size()},
                    {"outages_detected", link->outages_detected()},
                    {"frames_geometry_only", stage_.frames_geometry_only()},
                    {"check_period_s", network.check_period_s},
                    {"timeout_s", network.timeout_s}};
  }
  j["time_per_mapped_frame_ms"] = {{"cloud_median", runtime::percentile(cloud_ms_, 0.5)},
                                   {"insert_median", runtime::percentile(insert_ms_, 0.5)},
                                   {"layers_median", runtime::percentile(layers_ms_, 0.5)},
                                   {"esdf_median", runtime::percentile(esdf_ms_, 0.5)},
                                   {"median", runtime::percentile(total_ms_, 0.5)},
                                   {"p90", runtime::percentile(total_ms_, 0.9)},
                                   {"max", runtime::percentile(total_ms_, 1.0)}};
  j["memory"] = memory_;
  if (quality_) j["quality"] = quality_json(quality_->result(), *scenario_);
  if (quality_global_) j["quality_global"] = quality_json(quality_global_->result(), *scenario_);
  std::ofstream(out_ / "summary.json") << j.dump(2) << "\n";
  for (auto* csv : {&timing_, &obstacle_csv_}) csv->flush();  // complete while the session lives on
  return j;
}

}  // namespace navaid::experiments
