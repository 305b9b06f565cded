// navaid run's work, for every caller (the command, the trials, the reproductions, the tests): the
// sliding-window estimator on a recording, from its feature observations or, when it has none,
// from its images through the front end, replayed on one thread or in real time
// (estimator_pipeline.hpp); with a device (device.* keys, runtime/device_spec.hpp) every estimate also
// goes through mapping, the device's guidance and its cues (device_run.hpp). Writes the run
// folder (docs/estimator.md "navaid run", docs/full-device-runs.md).
#include "navaid/experiments/recording_run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/evaluation/absolute_trajectory_error.hpp"
#include "navaid/evaluation/enu_position_error.hpp"
#include "navaid/evaluation/start_alignment.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/experiments/progress.hpp"
#include "navaid/experiments/recording_mission.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/experiments/run_output_stream.hpp"
#include "navaid/experiments/run_topview.hpp"

#include "navaid/core/config_reads.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/experiments/device_requirements.hpp"
#include "navaid/experiments/device_run.hpp"
#include "navaid/experiments/figure_script.hpp"

namespace navaid::experiments {

namespace {

struct AteSummary {
  double rmse_m = 0;
  double path_length_m = 0;
  std::size_t poses = 0;
  evaluation::Similarity W_to_groundtruth;
};

/// ATE RMSE of the estimated positions after the 4-DOF (position + yaw) alignment onto ground
/// truth (compute_ate): roll and pitch are observable through gravity, the rest of
/// the estimator's W frame is arbitrary. Initializing frames carry no estimate and are left out.
std::optional<AteSummary> ate_4dof(const std::vector<io::StampedPose>& trajectory,
                                   const std::vector<io::StampedPose>& gt) {
  const auto pairs = evaluation::associate_poses(trajectory, gt);
  if (pairs.size() < 3) return std::nullopt;
  const auto ate = evaluation::compute_ate(pairs, {evaluation::AlignmentMode::kPosYaw, 0});
  AteSummary r;
  r.rmse_m = ate.position.rmse;
  r.poses = pairs.size();
  r.W_to_groundtruth = ate.transform;
  for (std::size_t i = 1; i < pairs.size(); ++i) r.path_length_m += (pairs[i].gt.t - pairs[i - 1].gt.t).norm();
  return r;
}

// Where the estimator's features come from.
enum class Input { kFeatures, kImages };


// Intensity and depth only: labels and confidence are not the estimator's business.
void load_tracking_images(RgbdFrame& frame) {
  if (frame.intensity_path.empty())
    throw IoError(frame.camera, "frame " + std::to_string(frame.index) + " at " + std::to_string(frame.t) +
                                    " ns has no intensity image");
  frame.intensity = io::read_intensity_image(frame.intensity_path);
  if (!frame.depth_path.empty()) frame.depth = io::read_depth_png(frame.depth_path, frame.depth_png_scale_m);
}

/// frontend.rate_hz: the estimator takes the camera's frames at this rate at most (as VINS-Mono's
/// `freq`), the first one and then each one at least a period (less 5 %, for timestamp jitter)
/// after the last one taken; the others are left out of the run.
void thin_camera_frames(io::Recording& recording, const std::string& camera, double rate_hz) {
  const auto period = static_cast<Timestamp>(0.95e9 / rate_hz);
  std::optional<Timestamp> last;
  std::vector<RgbdFrame> kept;
  for (auto& f : recording.frames) {
    if (f.camera == camera) {
      if (last && f.t - *last < period) continue;
      last = f.t;
    }
    kept.push_back(std::move(f));
  }
  recording.frames = std::move(kept);
}

double frontend_ms(const FrameTiming& r) { return r.frontend ? r.frontend->track_ms + r.frontend->load_ms : 0.0; }

/// stages.csv: every stage's cost per frame (the device's stages empty where it skipped a frame).
void write_stage_csv(const std::filesystem::path& file, const std::vector<FrameTiming>& frames,
                     const std::map<Timestamp, runtime::StageTimes>& device) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << "t_ns,frontend_ms,estimator_ms,mapping_ms,planning_ms,interaction_ms\n";
  for (const auto& r : frames) {
    out << fmt::format("{},{},{:.4f}", r.t, r.frontend ? fmt::format("{:.4f}", frontend_ms(r)) : "", r.estimator_ms);
    if (const auto it = device.find(r.t); it != device.end()) {
      out << fmt::format(",{:.4f},{:.4f},{:.4f}\n", it->second.mapping_ms, it->second.planning_ms,
                         it->second.interaction_ms);
    } else {
      out << ",,,\n";
    }
  }
}

nlohmann::ordered_json stage_summary(const std::vector<FrameTiming>& frames) {
  std::vector<double> fe, est;
  for (const auto& r : frames) {
    if (r.frontend) fe.push_back(frontend_ms(r));
    est.push_back(r.estimator_ms);
  }
  nlohmann::ordered_json j;
  j["frontend"] = runtime::stage_distribution(fe);
  j["estimator"] = runtime::stage_distribution(est);
  return j;
}

double stage_total_s(const nlohmann::ordered_json& stages) {
  double total = 0;
  for (const auto& [name, s] : stages.items()) total += s["total_s"].get<double>();
  return total;
}

/// The estimator's statistics: keyframes, solves, initialization, failures, the calibration it
/// estimated, residual diagnostics.
void add_estimator_summary(nlohmann::ordered_json& j, const estimation::SlidingWindowEstimator& estimator,
                           const estimation::EstimatorConfig& est_config, const io::Recording& recording) {
  const auto& st = estimator.statistics();
  j["keyframes"] = st.keyframes;
  j["solves"] = st.solves;
  j["solver_iterations"] = st.solver_iterations;
  j["solves_at_iteration_cap"] = st.solves_at_iteration_cap;
  j["marginalizations"] = st.marginalizations;
  j["marginalization_failures"] = st.marginalization_failures;
  j["covariance_failures"] = st.covariance_failures;
  j["initialization"] = {{"method", estimation::to_string(est_config.init_method)},
                         {"attempts", st.initialization_attempts},
                         {"failures", st.initialization_failures},
                         {"last_failure", st.last_initialization_failure},
                         {"still_gyro_bias", st.still_gyro_bias_initializations}};
  j["zero_velocity_frames"] = st.zero_velocity_frames;
  j["frames_out_of_time_order"] = st.frames_out_of_time_order;
  if (est_config.use_mag) j["mag_disturbed_states"] = st.mag_disturbed;
  if (st.failures > 0)
    spdlog::warn("{} implausible solve(s): {} window restart(s) in the same map frame, {} re-initialization(s) in a "
                 "new map frame (last: {})",
                 st.failures, st.restarts, st.map_frame_resets, st.last_failure);
  if (st.map_frame_resets > 0)
    spdlog::warn("the map frame W was reset: the ATE aligns the whole run at once and so also measures the jump");
  j["failures"] = {{"detection", est_config.failure_detection},
                   {"count", st.failures},
                   {"restarts", st.restarts},
                   {"map_frame_resets", st.map_frame_resets},
                   {"last", st.last_failure}};
  if (st.initialized_at_s >= 0 && !recording.imu.empty())
    j["initialization"]["time_s"] = st.initialized_at_s - ns_to_seconds(recording.imu.front().t);
  if (est_config.estimate_time_offset) j["camera_time_offset_s"] = estimator.camera_time_offset_s();
  if (est_config.estimate_extrinsic) {
    const SE3 T = estimator.camera_extrinsic();
    j["camera_extrinsic_T_B_C"] = {{"t", {T.t.x(), T.t.y(), T.t.z()}},
                                   {"q_wxyz", {T.q.w(), T.q.x(), T.q.y(), T.q.z()}}};
  }
  if (est_config.residual_diagnostics) {
    nlohmann::ordered_json res = nlohmann::ordered_json::object();
    for (const auto& [type, r] : st.residuals)
      res[type] = {{"factors", r.factors},
                   {"rows", r.rows},
                   {"chi2_per_row", r.rows ? r.squared_sum / static_cast<double>(r.rows) : 0.0},
                   {"fraction_beyond_3_sigma_rms",
                    r.factors ? static_cast<double>(r.beyond_3_sigma_rms) / static_cast<double>(r.factors) : 0.0}};
    j["residuals"] = res;
  }
}

/// The fraction of frames in each estimator mode.
nlohmann::ordered_json mode_fractions(const std::vector<evaluation::RunEstimate>& estimates) {
  std::map<std::string, std::size_t> modes;
  for (const auto& e : estimates) ++modes[std::string(to_string(e.mode))];
  nlohmann::ordered_json fractions = nlohmann::ordered_json::object();
  for (auto m : {EstimatorMode::kInitializing, EstimatorMode::kRgbdVio, EstimatorMode::kVio, EstimatorMode::kImuOnly,
                 EstimatorMode::kLost}) {
    const std::string name(to_string(m));
    fractions[name] = estimates.empty() ? 0.0 : static_cast<double>(modes[name]) / static_cast<double>(estimates.size());
  }
  return fractions;
}

/// Per-frame cost: the whole frame, the estimator's share and, with images, the front end's and
/// the image decoding's.
void add_frame_times(nlohmann::ordered_json& j, const std::vector<FrameTiming>& timings,
                     const runtime::EstimatorDriver& driver, bool imu_prediction) {
  std::vector<double> frame_ms, estimator_ms;
  frame_ms.reserve(timings.size());
  estimator_ms.reserve(timings.size());
  for (const auto& r : timings) {
    frame_ms.push_back(r.ms);
    estimator_ms.push_back(r.estimator_ms);
  }
  j["time_per_frame_ms"] = {{"median", runtime::percentile(frame_ms, 0.5)}, {"p99", runtime::percentile(frame_ms, 0.99)},
                            {"max", frame_ms.empty() ? 0.0 : *std::max_element(frame_ms.begin(), frame_ms.end())},
                            {"estimator_median", runtime::percentile(estimator_ms, 0.5)},
                            {"estimator_p99", runtime::percentile(estimator_ms, 0.99)}};
  if (driver.image_input()) {
    std::vector<double> track_ms, load_ms, live_ms;
    for (const auto& r : timings)
      if (r.frontend) {
        track_ms.push_back(r.frontend->track_ms);
        load_ms.push_back(r.frontend->load_ms);
        live_ms.push_back(r.ms - r.frontend->load_ms);
      }
    auto& t = j["time_per_frame_ms"];
    // What a camera handing over pixels would cost: the frame without decoding its PNGs.
    t["without_image_load_median"] = runtime::percentile(live_ms, 0.5);
    t["without_image_load_p99"] = runtime::percentile(live_ms, 0.99);
    t["frontend_median"] = runtime::percentile(track_ms, 0.5);
    t["frontend_p99"] = runtime::percentile(track_ms, 0.99);
    t["image_load_median"] = runtime::percentile(load_ms, 0.5);
    t["image_load_p99"] = runtime::percentile(load_ms, 0.99);
    const auto& source = driver.frontend_source();
    const auto& drift = source.drift_totals();
    j["frontend"] = {{"frames_tracked", source.frames_tracked()},
                     {"imu_prediction", imu_prediction},
                     {"drift_check", {{"checked", drift.checked}, {"corrected", drift.corrected}, {"dropped", drift.dropped}}}};
  }
}

/// How far the run is from the ground truth: 4-DOF ATE and NEES in the first state's frame. Returns
/// the ATE (for the top view's title) and the console's words.
std::pair<std::optional<AteSummary>, std::string> add_truth_comparison(nlohmann::ordered_json& j,
                                                                        const std::vector<io::StampedPose>& poses,
                                                                        const std::vector<evaluation::RunEstimate>& estimates,
                                                                        const std::vector<io::StampedPose>& gt) {
  std::string ate_text = "no ground truth";
  const auto ate = ate_4dof(poses, gt);
  if (ate) {
    j["ate"] = {{"alignment", "posyaw (4-DOF: yaw + translation)"},
                {"rmse_m", ate->rmse_m},
                {"path_length_m", ate->path_length_m},
                {"percent_of_path", ate->path_length_m > 0 ? 100.0 * ate->rmse_m / ate->path_length_m : 0.0},
                {"poses", ate->poses}};
    ate_text = fmt::format("ATE {:.3f} m over {:.1f} m ({:.2f} %)", ate->rmse_m, ate->path_length_m,
                           ate->path_length_m > 0 ? 100.0 * ate->rmse_m / ate->path_length_m : 0.0);
  }
  {
    // Consistency: NEES in the frame of the estimator's first state (the one its covariance grows
    // from); averaged over this run's frames (correlated in time: indicative; average the values
    // of independent seeds, e.g. with navaid ablate, for the chi-square test).
    const auto aligned = evaluation::align_to_first_state(estimates, gt);
    if (!aligned.empty()) {
      const auto nees = evaluation::first_state_nees(aligned, gt);
      j["nees"] = {{"frame", "first state (4-DOF: yaw + translation at the first estimate)"},
                   {"position_mean", nees.position_summary.average},
                   {"orientation_mean", nees.orientation_summary.average},
                   {"position_fraction_within_95", nees.position_summary.fraction_inside},
                   {"orientation_fraction_within_95", nees.orientation_summary.fraction_inside},
                   {"poses", aligned.size()}};
      ate_text += fmt::format("; mean NEES position {:.2f}, orientation {:.2f} (3 if consistent)",
                              nees.position_summary.average, nees.orientation_summary.average);
    }
  }
  return {ate, ate_text};
}

/// The registration to GPS (use_gps): the registered frames' error in ENU against the ground
/// truth, beside what registering the true path to the fixes allows.
nlohmann::ordered_json gps_comparison(const std::vector<evaluation::RunEstimate>& estimates,
                                      const std::vector<io::StampedPose>& gt, const io::Recording& recording,
                                      const estimation::EstimatorConfig& est_config, std::size_t gps_outliers) {
  // The simulator's ground truth lives in ENU at the recording's origin (T_ENU_W = identity).
  std::vector<io::StampedPose> enu;
  for (const auto& e : estimates)
    if (e.T_ENU_W && e.mode != EstimatorMode::kInitializing) enu.push_back({e.pose.t, *e.T_ENU_W * e.pose.T_W_B});
  nlohmann::ordered_json g;
  g["registered_frames"] = enu.size();
  g["outlier_fixes"] = gps_outliers;  // left out by the innovation gate (estimator.gps.outlier_gate)
  const auto error = evaluation::enu_position_error(enu, gt);
  if (error) {
    g["first_registered_s"] = ns_to_seconds(enu.front().t - recording.imu.front().t);
    g["enu_position_rmse_m"] = error->rmse_m;
    g["enu_horizontal_rmse_m"] = error->horizontal_rmse_m;
    g["enu_vertical_rmse_m"] = error->vertical_rmse_m;
    g["enu_position_max_m"] = error->max_m;
    g["note"] = "no alignment: ground truth taken as ENU at the recording's origin (simulator convention)";
    // What the fixes allow: the true path registered to them (eq. 6-7), to all at once and causally.
    std::vector<Timestamp> times;
    for (const auto& p : enu) times.push_back(p.t);
    estimation::GpsRegistrationOptions options;
    options.error_correlation_time_s = est_config.gps_correlation_time_s;
    const auto reference_json = [](const evaluation::EnuPositionError& e, const char* note) {
      return nlohmann::ordered_json{{"rmse_m", e.rmse_m},
                                    {"horizontal_rmse_m", e.horizontal_rmse_m},
                                    {"vertical_rmse_m", e.vertical_rmse_m},
                                    {"frames", e.poses},
                                    {"note", note}};
    };
    const Vec3& lever = recording.calibration.gps_lever_arm_B;
    if (const auto r = evaluation::rigid_registration_reference(recording.gps, gt, lever, *recording.origin, times, options))
      g["rigid_registration_reference"] =
          reference_json(*r, "the ground truth registered to all fixes (4-DOF): the multipath averaged over the walk");
    if (const auto r = evaluation::causal_registration_reference(recording.gps, gt, lever, *recording.origin, times, options))
      g["causal_registration_reference"] = reference_json(
          *r, "the ground truth registered to the fixes up to each frame (4-DOF), as a causal estimator sees them");
  }
  return g;
}

/// The device's part of the summary (its stages beside the estimator's, latency, guidance, cues,
/// the map) and stages.csv; returns the console's words.
std::string add_device_report(nlohmann::ordered_json& j, DeviceRun& device_run, const runtime::DeviceSpec& device,
                              const std::vector<FrameTiming>& timings, const std::filesystem::path& out) {
  nlohmann::ordered_json d = device_run.finish();
  j["device"] = {{"name", device.name},
                 {"guidance", std::string(runtime::to_string(device.guidance))},
                 {"actuator", std::string(interaction::to_string(device.actuator))},
                 {"speech", device.speech},
                 {"map_every", device.map_every}};
  write_stage_csv(out / "stages.csv", timings, device_run.device().stage_times());
  nlohmann::ordered_json stages = stage_summary(timings);
  for (auto& [name, value] : d["stages"].items()) stages[name] = value;
  j["stages"] = stages;
  for (const char* key : {"latency", "map_latency", "guidance", "plans", "cues", "estimates", "device_thread"})
    if (d.contains(key)) j[key] = d[key];
  j["mapping"] = d["mapping"];
  const double span_s = j["pipeline"]["recording_s"].get<double>();
  j["pipeline"]["stage_time_per_recording_s"] = span_s > 0 ? stage_total_s(j["stages"]) / span_s : 0.0;
  return fmt::format("; device {}: {} cues spoken, {} patterns sent, frame-to-cue latency p99 {:.1f} ms", device.name,
                     d["cues"]["outcomes"]["spoken"].get<std::size_t>(), d["cues"]["outcomes"]["sent"].get<std::size_t>(),
                     d["latency"]["p99_ms"].get<double>());
}

/// The recording with what the estimator needs checked: IMU with gyro, a camera, IMU noise.
io::Recording read_estimator_recording(const std::filesystem::path& path) {
  io::Recording recording = io::read_camera_recording(path, "IMU and camera data");
  if (recording.imu.empty()) throw Error(path.string() + ": no IMU data; the estimator needs an IMU");
  if (std::any_of(recording.imu.begin(), recording.imu.end(), [](const ImuSample& s) { return !s.has_gyro; }))
    throw Error(path.string() + ": IMU samples without gyro data (accelerometer only, as TUM RGB-D); the " +
                "estimator needs a gyro");
  if (recording.calibration.cameras.empty())
    throw Error(path.string() + ": no camera in the calibration; the estimator needs one");
  if (!recording.calibration.imu)
    throw Error(path.string() + ": no IMU noise densities in the calibration; the estimator needs them (for a "
                "ROS bag: --imu-noise KALIBR_IMU.yaml)");
  return recording;
}

/// What the estimator's camera brings: features or images, how many frames, whether any has
/// depth. Without depth the estimator runs as VIO (est_config.use_depth is cleared).
struct CameraInput {
  Input input = Input::kImages;
  std::size_t frames = 0;
  bool any_depth = false;
};

CameraInput camera_input(const io::Recording& recording, const std::string& camera, const std::filesystem::path& path,
                         estimation::EstimatorConfig& est_config) {
  const Input input = recording.features.empty() ? Input::kImages : Input::kFeatures;
  std::size_t camera_frames = 0;
  bool any_depth = false;
  if (input == Input::kFeatures) {
    for (const auto& f : recording.features)
      if (f.camera == camera) {
        ++camera_frames;
        for (const auto& o : f.features) any_depth = any_depth || o.depth_m.has_value();
      }
    if (!any_depth && est_config.use_depth) {
      // No observation has a depth (a camera without a depth sensor): VIO, as for images below.
      spdlog::info("{}: no feature has a depth: running as VIO", path.string());
      est_config.use_depth = false;
    }
  } else {
    for (const auto& f : recording.frames)
      if (f.camera == camera) {
        ++camera_frames;
        any_depth = any_depth || f.has_depth();
      }
    if (recording.frames.empty())
      throw Error(path.string() +
                  ": no camera data: neither feature observations (features.csv) nor image frames; the estimator "
                  "needs one of them");
    if (camera_frames == 0)
      throw Error(path.string() + ": no image frames of camera '" + camera + "', the estimator's camera");
    if (!any_depth && est_config.use_depth) {
      // Nothing to measure depth with: VIO (the back end would otherwise ask for a depth noise model).
      spdlog::info("{}: no depth images: running as VIO", path.string());
      est_config.use_depth = false;
    }
  }
  return {input, camera_frames, any_depth};
}

/// The recording as a feature-level one: its images and ground-truth landmarks (whose ids are the
/// simulator's tracks, not the front end's) left out, `tracked` as its features.csv.
void save_tracked_features(const io::Recording& recording, std::vector<FeatureFrame> tracked,
                           const std::filesystem::path& folder) {
  io::Recording saved = recording;
  saved.frames.clear();
  saved.landmarks.clear();
  saved.features = std::move(tracked);
  io::write_navaid_recording(saved, folder);
}

const ConfigKey<bool> kRealtimePrediction{"device.realtime_prediction", true,
                                          "--realtime: the device's stages work on the estimate predicted to a "
                                          "frame's arrival"};

// The run on a recording folder (run_recording converts a bag into one first).
std::string run_recording_folder(const RecordingRunOptions& a) {
  if (a.realtime) validate(a.realtime_options);
  const Config& config = a.config;
  if (!a.voice.empty() && !config.has("device.name")) throw UsageError("--voice needs a device (--device)");
  const std::vector<TimedVoiceCommand> voice = a.voice.empty() ? std::vector<TimedVoiceCommand>{}
                                                               : read_voice_commands(a.voice);
  const ConfigReads reads(config);  // config.yaml: the given keys and the defaults the run used
  estimation::EstimatorConfig est_config = estimation::read_estimator_config(config);
  const estimation::FrontendConfig frontend_config = estimation::read_frontend_config(config);
  const double camera_rate_hz = get(config, frontend_rate_key());
  const std::optional<runtime::DeviceSpec> device =
      config.has("device.name") ? std::optional<runtime::DeviceSpec>(runtime::read_device_spec(config)) : std::nullopt;
  // A device maps as its own stage (runtime/device.hpp); mapping.enabled maps without one.
  const bool mapping_enabled = !device && get(config, defaulting_to(mapping_enabled_key(), false));
  const mapping::MapperConfig mapper_config = mapping::read_mapper_config(config);
  MapSessionOptions map_options;
  runtime::MappingStageOptions stage_options = runtime::read_mapping_stage_options(config);
  config.reject_unknown_keys(run_schema(device ? &*device : nullptr));
  if (est_config.leaving_anchor == estimation::LeavingAnchorPolicy::kReuse && est_config.loss == estimation::LossKind::kNone)
    spdlog::warn("estimator.features.leaving_anchor=reuse without a robust loss counts reused observations at full "
                 "weight: it diverged on 4 of 20 Monte-Carlo seeds of lab-walk-1 (docs/estimator.md, Consistency); "
                 "use leaving_anchor=reanchor for Gaussian studies");

  io::Recording recording = read_estimator_recording(a.recording);
  // The estimator's camera (its default: the rig's first); the front end tracks the same one.
  const std::string camera = recording.calibration.cameras.front().name;
  if (camera_rate_hz > 0) thin_camera_frames(recording, camera, camera_rate_hz);
  if (device) {
    const std::vector<std::string> missing = missing_for_device(*device, recording, a.recording);
    if (!missing.empty())
      throw Error(fmt::format("{}: cannot serve device {}: it lacks {}", a.recording.string(), device->name,
                              fmt::join(missing, "; ")));
  }
  const CameraInput camera_in = camera_input(recording, camera, a.recording, est_config);
  const Input input = camera_in.input;
  const std::size_t camera_frames = camera_in.frames;
  const bool any_depth = camera_in.any_depth;
  if (!a.save_features.empty() && input == Input::kFeatures)
    throw UsageError("--save-features saves what the image front end tracks; " + a.recording.string() +
                     " is feature-level already (features.csv)");
  if (!a.save_features.empty() && std::filesystem::exists(a.save_features) &&
      !std::filesystem::is_empty(a.save_features))
    throw UsageError("--save-features " + a.save_features.string() + ": the folder holds files already");

  estimation::SlidingWindowEstimator estimator(recording.calibration, est_config, camera, recording.origin);
  std::optional<runtime::EstimatorDriver> driver_storage;
  if (input == Input::kImages) {
    // Replay is deterministic only with OpenCV's parallel loops off (they change the tracks' last bits).
    estimation::set_opencv_threads(1);
    driver_storage.emplace(std::move(estimator),
                           estimation::ImageFeatureSource(recording.calibration, frontend_config, camera,
                                                          &load_tracking_images));
  } else {
    driver_storage.emplace(std::move(estimator));
  }
  runtime::EstimatorDriver& driver = *driver_storage;
  std::filesystem::create_directories(a.out);
  // estimates.csv, trajectory.tum and timing.csv grow as the run goes; the run keeps a compact
  // record of each frame only.
  RunOutputStream stream(a.out, a.realtime);

  runtime::PipelineInput pipeline_input{recording, camera, driver, {}, false, {}, {}, {}, {}, {}};
  pipeline_input.on_record = [&](const runtime::FrameRecord& r) { stream.add(r); };
  if (driver.image_input()) {
    pipeline_input.load_images = &load_tracking_images;
    pipeline_input.imu_prediction = frontend_config.imu_prediction;
  }
  Progress progress(std::string(driver.image_input() ? "tracking and estimating" : "estimating") +
                        (a.realtime ? " (real time)" : ""),
                    camera_frames);
  pipeline_input.on_progress = [&progress](std::size_t frames) { progress.update(frames); };
  std::vector<FeatureFrame> tracked;  // --save-features
  if (!a.save_features.empty()) pipeline_input.on_tracked = [&tracked](const FeatureFrame& f) { tracked.push_back(f); };
  // mapping.enabled: the map is built as the estimates come (map/, the same folder navaid map writes).
  std::optional<runtime::MappingStage> map_stage;
  std::optional<MapSession> map_session;
  std::map<Timestamp, const RgbdFrame*> frame_at;
  if (mapping_enabled) {
    if (!any_depth)
      throw Error(a.recording.string() + ": mapping.enabled=true needs RGB-D frames with depth; this recording has " +
                  (input == Input::kFeatures ? "feature observations" : "no depth images"));
    const auto& cams = recording.calibration.cameras;
    const auto cam = std::find_if(cams.begin(), cams.end(), [&](const CameraCalibration& c) { return c.name == camera; });
    map_options.frames_total = camera_frames;
    map_options.align_to = groundtruth_poses(recording);
    map_stage.emplace(mapper_config, *cam, stage_options);
    map_session.emplace(*map_stage, a.recording, a.out / "map", map_options);
    for (const auto& f : recording.frames)
      if (f.camera == camera) frame_at[f.t] = &f;
    pipeline_input.on_estimate = [&](const StateEstimate& e, std::chrono::steady_clock::time_point) {
      if (const auto it = frame_at.find(e.t); it != frame_at.end())
        map_session->record(*it->second, e, map_stage->add(*it->second, e));
    };
  }
  std::unique_ptr<DeviceRun> device_run;
  if (device) {
    const auto& cams = recording.calibration.cameras;
    const auto cam = std::find_if(cams.begin(), cams.end(), [&](const CameraCalibration& c) { return c.name == camera; });
    map_options.frames_total = camera_frames;
    map_options.align_to = groundtruth_poses(recording);
    stage_options.network_start = recording_start(recording);
    DeviceRunOptions device_options;
    device_options.device.drop_when_full = a.realtime;
    device_options.device.queue_capacity = a.device_queue;
    device_options.device.mapping = stage_options;
    device_options.figures = a.plot;
    const bool prediction = get(config, kRealtimePrediction);
    device_options.device.predict_at_arrival = a.realtime && prediction;
    device_run = std::make_unique<DeviceRun>(*device, config, recording, a.recording, *cam, a.out, map_options,
                                             device_options);
    for (const auto& [t, command] : voice) device_run->device().on_voice_command(stage_options.network_start + t, command);
    pipeline_input.on_estimate = [&](const StateEstimate& e, std::chrono::steady_clock::time_point arrival) {
      device_run->device().on_estimate(e, arrival);
    };
    if (device_options.device.predict_at_arrival)
      pipeline_input.on_frame_arrival = [&](Timestamp t, std::chrono::steady_clock::time_point arrival) {
        device_run->device().on_frame_arrival(t, arrival);
      };
  }
  runtime::PipelineResult result;
  try {
    result = a.realtime ? runtime::realtime_pipeline(pipeline_input, a.realtime_options) : runtime::replay_pipeline(pipeline_input);
    progress.finish();
  } catch (const std::exception& e) {
    if (!device_run) throw;
    // A stage failed: keep what the run made so far, and say where it stopped.
    std::ofstream(a.out / "error.txt") << e.what() << "\n";
    stream.flush();
    try {
      device_run->finish();
    } catch (const std::exception& flush_error) {
      spdlog::warn("while writing the run's outputs after the failure: {}", flush_error.what());
    }
    throw;
  }
  stream.close();
  if (!a.save_features.empty()) save_tracked_features(recording, std::move(tracked), a.save_features);
  // The walk is over; what follows reads the whole run at once (scripts/long-walk.py tells the
  // two phases apart by this line).
  spdlog::info("{} frames estimated; evaluating the run", stream.estimates().size());
  const std::vector<evaluation::RunEstimate>& estimates = stream.estimates();
  std::vector<io::StampedPose> poses;  // trajectory.tum's
  poses.reserve(estimates.size());
  for (const auto& e : estimates)
    if (e.mode != EstimatorMode::kInitializing) poses.push_back({e.pose.t, e.pose.T_W_B});
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());

  const auto& st = driver.estimator().statistics();
  nlohmann::ordered_json j;
  j["recording"] = a.recording.string();
  j["input"] = input == Input::kImages ? "images (front end)" : "features";
  j["depth"] = est_config.use_depth;
  if (!a.save_features.empty()) j["saved_features"] = a.save_features.string();
  j["frames"] = estimates.size();
  add_estimator_summary(j, driver.estimator(), est_config, recording);
  const nlohmann::ordered_json fractions = mode_fractions(estimates);
  j["mode_fractions"] = fractions;
  if (map_session) {
    const auto m = map_session->finish({{"recording", std::filesystem::absolute(a.recording).string()},
                                        {"poses", "the estimator's, as the run went"}});
    j["mapping"] = {{"folder", "map"}, {"frames", m["frames"]}, {"time_per_mapped_frame_ms", m["time_per_mapped_frame_ms"]}};
    if (m.contains("quality")) j["mapping"]["quality"] = m["quality"]["occupancy"];
  }
  add_frame_times(j, stream.timings(), driver, frontend_config.imu_prediction);
  // The ground truth's poses, once for every measure below (an hour's is ~50 MB).
  std::vector<io::StampedPose> gt;
  gt.reserve(recording.groundtruth.size());
  for (const auto& g : recording.groundtruth) gt.push_back({g.t, g.T_W_B});
  const auto [ate, ate_text] = add_truth_comparison(j, poses, estimates, gt);
  if (est_config.use_gps) j["gps"] = gps_comparison(estimates, gt, recording, est_config, st.gps_outliers);
  {
    const double span_s = ns_to_seconds(recording.imu.back().t - recording.imu.front().t);
    j["pipeline"] = {{"mode", a.realtime ? "realtime" : "replay"},
                     {"wall_s", result.wall_s},
                     {"recording_s", span_s},
                     {"realtime_factor", result.wall_s > 0 ? span_s / result.wall_s : 0.0}};
    if (a.realtime) j["realtime"] = result.realtime;
  }
  if (!!a.plot) {
    // A figure is a convenience: failing to draw it does not fail the run.
    try {
      const std::string title =
          ate ? fmt::format("{}: ATE {:.3f} m over {:.1f} m (4-DOF)", a.recording.filename().string(), ate->rmse_m,
                            ate->path_length_m)
              : a.recording.filename().string();
      draw_run_topview(a.out, estimates, recording.groundtruth,
                       ate ? std::optional<evaluation::Similarity>(ate->W_to_groundtruth) : std::nullopt, title);
    } catch (const std::exception& e) {
      spdlog::warn("topview.png not drawn: {}", e.what());
    }
  }
  const std::string device_text = device_run ? add_device_report(j, *device_run, *device, stream.timings(), a.out) : "";
  std::ofstream(a.out / "summary.json") << j.dump(2) << "\n";
  if (device_run && a.plot) {
    try {
      run_figure_script("run_report.py", {a.out.string(), "--out", (a.out / "report.html").string()});
    } catch (const std::exception& e) {
      spdlog::warn("report.html not written: {}", e.what());
    }
  }
  std::string frontend_text;
  if (driver.image_input())
    frontend_text = fmt::format(" (front end {:.1f})", j["time_per_frame_ms"]["frontend_median"].get<double>());
  return fmt::format(
      "wrote {}: {} frames from {}, {} keyframes, {:.0f} % RGBD-VIO, {:.0f} % VIO, median {:.1f} ms/frame{}; {}\n",
      a.out.string(), estimates.size(), input == Input::kImages ? "images" : "features", st.keyframes,
      100.0 * fractions["rgbd-vio"].get<double>(), 100.0 * fractions["vio"].get<double>(),
      j["time_per_frame_ms"]["median"].get<double>(),
      frontend_text, ate_text + device_text);
}

}  // namespace

std::string run_recording(const RecordingRunOptions& options) {
  if (options.recording.empty()) throw UsageError("--recording is required");
  if (options.out.empty()) throw UsageError("--out is required");
  const bool bag = std::filesystem::is_regular_file(options.recording) && io::is_ros_bag(options.recording);
  if (!bag) {
    if (options.bag_options_given)
      throw UsageError("the ROS bag options (--topic, --topics, --bag-preset, --camchain, --imu-noise, "
                       "--depth-pair-window, --depth-range) need a bag as --recording; " + options.recording.string() + " is not one");
    return run_recording_folder(options);
  }
  // The bag's images are extracted once, into a navaid recording inside the run folder.
  RecordingRunOptions a = options;
  a.recording = options.out / "recording";
  io::RosBagConversion conversion = options.bag;
  conversion.overwrite = true;
  const io::Recording converted = io::convert_ros_bag(options.recording, a.recording, conversion);
  spdlog::info("{}: converted into {} ({} frames, {} imu, {} warnings)", options.recording.string(),
               a.recording.string(), converted.frames.size(), converted.imu.size(), converted.report.total());
  for (const auto& w : converted.report.warnings)
    spdlog::warn("{}: {}{}", w.source, w.message, w.count > 1 ? fmt::format(" (x{})", w.count) : "");
  return run_recording_folder(a);
}

ConfigSchema recording_run_schema() {
  return ConfigSchema().add(frontend_rate_key()).add(mapping_enabled_key()).add(kRealtimePrediction);
}

}  // namespace navaid::experiments
