#include "navaid/simulation/simulator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <mutex>
#include <thread>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "navaid/simulation/frame_rng.hpp"
#include "navaid/simulation/recorded_motion.hpp"
#include "navaid/simulation/render_cache.hpp"
#include "navaid/simulation/sensor_streams.hpp"
#include "navaid/simulation/time_grid.hpp"
#include "navaid/simulation/top_view.hpp"

namespace navaid::simulation {

namespace fs = std::filesystem;

namespace {

std::string render_key(const Scenario& scenario, const SimulationConfig& c, const std::vector<Timestamp>& times) {
  const auto& cam = c.camera;
  const auto& w = c.walker;
  const auto& r = c.render;
  const SE3 T = cam.T_B_C;
  std::string key = fmt::format(
      "navaid render cache\nrenderer {}\nscenario {} seed {} moving {}\n"
      "camera {}x{} f {} {} c {} {} distortion {} [{}] T_B_C {} {} {} {} {} {} {}\n"
      "walker {} {} {} {} {} {} {} {} {} {} {} {}\nrender {} {} {} {} {} {} {} {} {} {} {}\nframes {}",
      kRendererVersion, scenario.name, scenario.seed, scenario.moving.size(), cam.width, cam.height, cam.fx, cam.fy,
      cam.cx, cam.cy, static_cast<int>(cam.distortion), fmt::join(cam.distortion_coeffs, " "), T.q.w(), T.q.x(), T.q.y(),
      T.q.z(), T.t.x(), T.t.y(), T.t.z(), w.speed_mps, w.ramp_time_s, w.mount_height_m, w.ground_z_m,
      w.corner_spacing_m, w.step_frequency_hz, w.bob_amplitude_m, w.sway_amplitude_m, w.pitch_amplitude_rad,
      w.roll_amplitude_rad, w.scan_amplitude_rad, w.scan_period_s, r.min_depth, r.max_depth, r.max_ray_distance,
      r.render_depth, r.render_labels, r.render_intensity, r.sun_direction_W.x(), r.sun_direction_W.y(),
      r.sun_direction_W.z(), r.ambient, static_cast<int>(r.no_hit_class), times.size());
  for (const Timestamp t : times) key += fmt::format(" {}", t);
  return key + "\n";
}

std::string image_name(const char* folder, const std::string& camera, Timestamp t) {
  return fmt::format("{}/{}_{}.png", folder, camera, t);
}

// The image-mode frame stage: render (or load from the cache), add noise and label confusion,
// write the PNGs into the output folder. Frames are independent, so workers take them in any order.
// The body's pose at time t_s since the motion's epoch (a simulated walk's trajectory time, or
// the seconds since a recording's first sample).
using BodyPose = std::function<SE3(double t_s)>;

// Camera stamps of frames taken at `rel` after `epoch` (IMU clock): the camera clock's.
Timestamp frame_stamp(const SimulationConfig& config, Timestamp epoch, Timestamp rel) {
  return camera_stamp(config, rel) - kSimulationEpoch + epoch;
}

struct FrameStage {
  const Scenario& scenario;
  const SimulationConfig& config;
  const BodyPose& body_pose;
  Timestamp epoch;
  const RayCaster& world;
  const fs::path& out;
  const std::vector<Timestamp>& times;  // relative to the epoch
  std::optional<RenderCache> cache;
  double depth_unit_m;
  LabelConfusionModel confusion;

  std::vector<RgbdFrame> frames;
  std::vector<double> valid_fraction;
  std::atomic<std::size_t> rendered{0};

  void run(const SimulateOptions& options) {
    const auto camera = make_camera_model(config.camera, "sensor.camera");
    const RgbdRenderer renderer(world, *camera);
    frames.resize(times.size());
    valid_fraction.resize(times.size());
    for (const char* folder : {"rgb", "depth", "labels", "confidence"}) fs::create_directories(out / folder);

    std::atomic<std::size_t> next{0}, done{0};
    std::mutex mutex;
    std::exception_ptr failure;
    auto worker = [&] {
      try {
        RenderedFrame clean;
        for (std::size_t i = next++; i < times.size(); i = next++) {
          process(i, renderer, clean);
          const std::size_t n = ++done;
          std::lock_guard<std::mutex> lock(mutex);
          if (options.on_frame) options.on_frame(n, times.size());
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = times.size();
      }
    };
    const int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
  }

  void process(std::size_t i, const RgbdRenderer& renderer, RenderedFrame& clean) {
    const double t_s = ns_to_seconds(times[i]);
    const SE3 T_W_C = body_pose(t_s) * config.camera.T_B_C;
    if (cache && cache->has(i)) {
      clean = cache->load(i);
    } else {
      const auto moving = moving_caster(scenario, t_s, T_W_C.t);
      renderer.render(T_W_C, config.render, clean, moving ? &*moving : nullptr);
      clean.depth = quantize_depth(clean.depth, depth_unit_m);
      if (cache) cache->store(i, clean);
      ++rendered;
    }
    const NoisyRgbd noisy = apply_rgbd_noise(clean, config.rgbd_noise, config.seed, i);
    const LabelPrediction labels = confusion.apply(clean.labels, config.seed, i);

    RgbdFrame f;
    f.t = frame_stamp(config, epoch, times[i]);
    f.index = i;
    f.camera = config.camera.name;
    f.intensity_path = (out / image_name("rgb", f.camera, f.t)).string();
    f.depth_path = (out / image_name("depth", f.camera, f.t)).string();
    f.labels_path = (out / image_name("labels", f.camera, f.t)).string();
    f.confidence_path = (out / image_name("confidence", f.camera, f.t)).string();
    f.depth_png_scale_m = io::kNavaidDepthScaleM;
    io::write_png(f.intensity_path, noisy.intensity);
    io::write_png(f.depth_path, io::depth_to_png_units(noisy.depth, io::kNavaidDepthScaleM, f.depth_path));
    io::write_png(f.labels_path, labels.labels);
    io::write_png(f.confidence_path, io::confidence_to_png_units(labels.confidence, f.confidence_path));
    const auto valid = std::count_if(noisy.depth.pixels.begin(), noisy.depth.pixels.end(), [](float z) { return z > 0; });
    valid_fraction[i] = static_cast<double>(valid) / static_cast<double>(std::max<std::size_t>(1, noisy.depth.pixels.size()));
    frames[i] = std::move(f);
  }
};

std::vector<FeatureFrame> simulate_features(const Scenario& scenario, const SimulationConfig& config,
                                            const BodyPose& body_pose, Timestamp epoch, const RayCaster& world,
                                            const std::vector<Timestamp>& times, const std::vector<Landmark>& landmarks,
                                            const SimulateOptions& options) {
  const auto camera = make_camera_model(config.camera, "sensor.camera");
  FeatureObserver observer(world, *camera, landmarks, config.features);
  std::mt19937_64 rng(model_seed(config.seed, ModelStream::kFeatures));
  std::vector<FeatureFrame> frames;
  frames.reserve(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t_s = ns_to_seconds(times[i]);
    const SE3 T_W_C = body_pose(t_s) * config.camera.T_B_C;
    const auto moving = moving_caster(scenario, t_s, T_W_C.t);
    FeatureFrame f = observer.observe(frame_stamp(config, epoch, times[i]), T_W_C, rng, moving ? &*moving : nullptr);
    frames.push_back(std::move(f));  // also when empty: the camera saw nothing it could track
    if (options.on_frame) options.on_frame(i + 1, times.size());
  }
  return frames;
}

// P(predicted | true) of the simulated segmentation, so that consumers can turn a label and its
// confidence into class probabilities (LabelConfusionModel::posterior does the same).
void write_confusion_matrix(const fs::path& file, const ConfusionMatrix& m) {
  std::string text = "true\\predicted";
  for (const auto& c : semantic_classes()) text += fmt::format(",{}", c.name);
  text += "\n";
  for (const auto& t : semantic_classes()) {
    text += std::string(t.name);
    for (double p : m[static_cast<std::size_t>(t.id)]) text += fmt::format(",{}", p);
    text += "\n";
  }
  std::ofstream(file, std::ios::binary) << text;
}

void write_top_view(const Scenario& scenario, const RayCaster& world, const std::vector<Vec2>& walked, const fs::path& file) {
  const double width_m = scenario.extent.max.x() - scenario.extent.min.x();
  io::write_png(file.string(), render_top_view(world, scenario_map_options(scenario, std::min(1200.0, width_m / 0.02), &walked)).image, 6);
}

// The feature stage's counts in the summary.
void count_observations(const std::vector<FeatureFrame>& features, SimulationSummary& summary) {
  std::size_t with_depth = 0;
  for (const auto& f : features) {
    summary.observations += f.features.size();
    for (const auto& o : f.features) with_depth += o.depth_m.has_value();
  }
  summary.depth_observation_fraction =
      summary.observations > 0 ? static_cast<double>(with_depth) / static_cast<double>(summary.observations) : 0.0;
}

// The image stage's frames into the recording, its confusion matrix and counts.
void take_frames(FrameStage& stage, const fs::path& out, io::Recording& rec, SimulationSummary& summary) {
  rec.frames = std::move(stage.frames);
  write_confusion_matrix(out / "label_confusion.csv", stage.confusion.matrix());
  summary.rendered_frames = stage.rendered;
  for (double v : stage.valid_fraction) summary.valid_depth_fraction += v / static_cast<double>(stage.valid_fraction.size());
}

// Refuses a non-empty folder unless overwriting; creates it.
void prepare_output(const fs::path& out, const SimulateOptions& options) {
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_empty(out, ec) && !options.overwrite)
    throw UsageError(out.string() + " exists and is not empty; pass --overwrite to replace its recording files");
  fs::create_directories(out, ec);
  if (ec) throw IoError(out.string(), "cannot create the output folder: " + ec.message());
  if (options.overwrite)  // images of an earlier run would otherwise stay beside the new ones
    for (const char* folder : {"rgb", "depth", "labels", "confidence"}) fs::remove_all(out / folder, ec);
}

// Writes the recording with its ground truth as TUM, the targets and the top view; fills the
// summary's counts.
void finish_recording(const Scenario& scenario, const RayCaster& world, const SimulationConfig& config,
                      const io::Recording& rec, const fs::path& out, SimulationSummary& summary) {
  io::NavaidWriteOptions write_options;
  write_options.overwrite = true;  // the folder was checked above; it now holds our own images
  write_options.images_in_place = true;
  io::write_navaid_recording(rec, out, write_options);

  // Ground truth of the tagged target objects (hand guidance); only scenarios that have them.
  write_scenario_targets(scenario, out / io::kTargetsCsv);

  std::vector<io::StampedPose> poses;
  poses.reserve(rec.groundtruth.size());
  for (const auto& g : rec.groundtruth) poses.push_back({g.t, g.T_W_B});
  io::write_tum_trajectory(out / "groundtruth.tum", poses);

  std::vector<Vec2> walked;
  for (std::size_t i = 0; i < rec.groundtruth.size(); i += 10) walked.push_back(rec.groundtruth[i].T_W_B.t.head<2>());
  write_top_view(scenario, world, walked, out / "topview.png");

  summary.imu = rec.imu.size();
  summary.frames = config.mode == SimulationMode::kImages ? rec.frames.size() : rec.features.size();
  summary.gps = rec.gps.size();
  summary.mag = rec.mag.size();
  summary.groundtruth = rec.groundtruth.size();
  summary.landmarks = rec.landmarks.size();
}

}  // namespace

void write_scenario_targets(const Scenario& scenario, const fs::path& file) {
  if (scenario.targets.empty()) {
    std::error_code ec;
    fs::remove(file, ec);  // a stale file of an overwritten recording
    return;
  }
  std::vector<io::TargetGroundTruth> targets;
  for (const TargetObject& t : scenario.targets)
    targets.push_back({t.name, t.semantic, t.tag_family, t.tag_id, t.tag_size_m, t.center_W, t.half_extents, t.T_W_tag});
  io::write_targets_csv(file, targets);
}

namespace {

/// The scenario's path walked `laps` times; more than one lap needs a closed path.
std::vector<Vec2> walking_path(const Scenario& scenario, int laps) {
  std::vector<Vec2> path = scenario.path;
  if (laps == 1) return path;
  if (path.size() < 3 || (path.front() - path.back()).norm() > 0.01)
    throw ConfigError("simulation", "simulation.laps",
                      "scenario '" + scenario.name + "' does not walk a closed path: it has one lap only");
  for (int lap = 1; lap < laps; ++lap) path.insert(path.end(), scenario.path.begin() + 1, scenario.path.end());
  return path;
}

}  // namespace

SimulationSummary simulate(const Scenario& scenario, const SimulationConfig& config, const fs::path& out,
                           const SimulateOptions& options) {
  prepare_output(out, options);

  WalkerConfig walker = config.walker;
  walker.ground_z_m = scenario.ground_z_m;
  const WalkerTrajectory trajectory(walking_path(scenario, config.laps), walker);
  const BodyPose body_pose = [&trajectory](double t_s) { return trajectory.state(t_s).T_W_B; };
  const double t_begin = -config.still_time_s;
  const double t_end = config.duration_s > 0 ? std::min(t_begin + config.duration_s, trajectory.duration()) : trajectory.duration();
  const RayCaster world(scenario.world);

  SimulationSummary summary;
  summary.duration_s = t_end - t_begin;
  summary.path_length_m = trajectory.length();

  io::Recording rec;
  rec.format = "navaid";
  rec.origin = scenario.origin;
  rec.calibration.cameras = {config.camera};
  rec.calibration.imu = config.imu;

  // IMU and ground truth (at the IMU rate, with the true biases).
  ImuModel imu(config.imu, imu_options(config));
  SimulatedImuStream imu_stream = simulate_imu_stream(trajectory, imu, t_begin, t_end, kSimulationEpoch);
  rec.imu = std::move(imu_stream.samples);
  rec.groundtruth = std::move(imu_stream.ground_truth);
  for (std::size_t i = 1; i < rec.groundtruth.size(); ++i)
    summary.walked_m += (rec.groundtruth[i].T_W_B.t - rec.groundtruth[i - 1].T_W_B.t).norm();

  // Camera: images or feature observations.
  const std::vector<Timestamp> frame_times = time_grid(t_begin, t_end, config.camera.rate_hz);
  const auto frames_start = std::chrono::steady_clock::now();
  if (config.mode == SimulationMode::kImages) {
    const double unit = cache_depth_unit_m(config.render.max_depth);
    FrameStage stage{scenario,    config, body_pose, kSimulationEpoch, world, out, frame_times, std::nullopt, unit,
                     LabelConfusionModel(config.label_confusion), {}, {}, {}};
    if (options.cache_dir) stage.cache.emplace(*options.cache_dir, render_key(scenario, config, frame_times), unit);
    stage.run(options);
    take_frames(stage, out, rec, summary);
  } else {
    rec.landmarks = generate_landmarks(world, trajectory, config.features, scenario.seed);
    rec.features = simulate_features(scenario, config, body_pose, kSimulationEpoch, world, frame_times, rec.landmarks, options);
    count_observations(rec.features, summary);
  }
  summary.frames_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - frames_start).count();

  // GNSS at the antenna, with multipath growing where buildings hide the low sky.
  if (config.gps_enabled) {
    GnssModelConfig gps = config.gps;
    gps.seed = model_seed(config.seed, ModelStream::kGps);
    GnssModel model(gps, scenario.origin);
    rec.calibration.gps_lever_arm_B = config.mount.gps_lever_arm_B;
    rec.calibration.gps_rate_hz = gps.rate_hz;
    for (const Timestamp rel : time_grid(t_begin, t_end, gps.rate_hz)) {
      const SE3 T_W_B = trajectory.state(ns_to_seconds(rel)).T_W_B;
      const Vec3 antenna = T_W_B * config.mount.gps_lever_arm_B;
      if (auto fix = model.measure(kSimulationEpoch + rel, antenna, SE3::identity(), urban_canyon_factor(world, antenna)))
        rec.gps.push_back(*fix);
    }
  }
  if (config.mag_enabled) {
    MagnetometerModelConfig mag = config.mag;
    mag.seed = model_seed(config.seed, ModelStream::kMag);
    MagnetometerModel model(mag);
    rec.calibration.mag_rate_hz = config.mag_rate_hz;
    for (const Timestamp rel : time_grid(t_begin, t_end, config.mag_rate_hz))
      rec.mag.push_back(model.measure(kSimulationEpoch + rel, SE3::identity(), trajectory.state(ns_to_seconds(rel)).T_W_B));
  }

  finish_recording(scenario, world, config, rec, out, summary);
  return summary;
}

SimulationSummary simulate_recorded_motion(const Scenario& scenario, const SimulationConfig& config,
                                           const io::Recording& source, const fs::path& out,
                                           const SimulateOptions& options) {
  if (source.imu.empty()) throw UsageError("the recording has no IMU samples to keep");
  if (source.groundtruth.size() < 2) throw UsageError("the recording has no ground-truth trajectory to fly the camera along");
  const RecordedMotion motion(source.groundtruth);
  const Timestamp begin = std::max(source.imu.front().t, motion.begin());
  Timestamp end = std::min(source.imu.back().t, motion.end());
  if (config.duration_s > 0) end = std::min(end, begin + seconds_to_ns(config.duration_s));
  if (!(end > begin)) throw UsageError("the recording's IMU samples and ground truth do not overlap in time");
  prepare_output(out, options);

  SimulationSummary summary;
  summary.duration_s = ns_to_seconds(end - begin);
  io::Recording rec;
  rec.format = "navaid";
  rec.origin = scenario.origin;
  rec.calibration.cameras = {config.camera};
  rec.calibration.imu = config.imu;
  for (const ImuSample& m : source.imu)
    if (m.t >= begin && m.t <= end) rec.imu.push_back(m);
  for (const GroundTruthState& g : source.groundtruth)
    if (g.t >= begin && g.t <= end) rec.groundtruth.push_back(g);
  for (std::size_t i = 1; i < rec.groundtruth.size(); ++i)
    summary.walked_m += (rec.groundtruth[i].T_W_B.t - rec.groundtruth[i - 1].T_W_B.t).norm();
  summary.path_length_m = summary.walked_m;

  const RayCaster world(scenario.world);
  const BodyPose body_pose = [&motion, begin](double t_s) { return motion.pose_at(begin + seconds_to_ns(t_s)); };
  const std::vector<Timestamp> frame_times = time_grid(0.0, ns_to_seconds(end - begin), config.camera.rate_hz);
  const auto frames_start = std::chrono::steady_clock::now();
  if (config.mode == SimulationMode::kImages) {
    const double unit = cache_depth_unit_m(config.render.max_depth);
    FrameStage stage{scenario,    config, body_pose, begin, world, out, frame_times, std::nullopt, unit,
                     LabelConfusionModel(config.label_confusion), {}, {}, {}};
    stage.run(options);
    take_frames(stage, out, rec, summary);
  } else {
    // Landmarks seeded from the flown positions themselves (the body flies where it looks from).
    std::mt19937_64 rng(scenario.seed);
    std::normal_distribution<double> normal;
    double since_last = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < rec.groundtruth.size(); ++i) {
      if (i > 0) since_last += (rec.groundtruth[i].T_W_B.t - rec.groundtruth[i - 1].T_W_B.t).norm();
      if (since_last < config.features.landmark_spacing_m && i + 1 < rec.groundtruth.size()) continue;
      seed_landmarks_from(world, rec.groundtruth[i].T_W_B.t, config.features, rng, normal, rec.landmarks);
      since_last = 0;
    }
    rec.features = simulate_features(scenario, config, body_pose, begin, world, frame_times, rec.landmarks, options);
    count_observations(rec.features, summary);
  }
  summary.frames_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - frames_start).count();
  finish_recording(scenario, world, config, rec, out, summary);
  return summary;
}

}  // namespace navaid::simulation
