// navaid hand-guide: W-ROMA hand guidance (Sec. IV) on every frame of a recording: the AprilTag
// detector on the intensity image, the depth patch around the tag's centre, HandGuidance with the
// frame's StateEstimate (a navaid run's estimates, the ground truth, or none); writes
// guidance.csv, guidance_timeline.csv (the input of `navaid cues`), summary.json and config.yaml and prints the frames per case and hand direction.
// With a simulated recording (targets.csv and ground truth) every frame is also checked against
// the truth: whether the tag is in view, the detected centre's pixel error, target_H's error.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "input_option.hpp"
#include "map_poses.hpp"
#include "navaid/core/camera.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/runtime/tag_target.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/core/csv_field.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/hand_guidance.hpp"
#include "navaid/simulation/apriltag_image.hpp"
#include "navaid/experiments/progress.hpp"

namespace navaid::cli {

using experiments::Progress;


namespace {

namespace fs = std::filesystem;
using planning::GuidanceCommand;
using planning::GuidanceReason;
using planning::HandDirection;

struct HandGuideArgs {
  fs::path recording, estimate, out, config_file;
  std::string poses;  // "" = from --estimate when given, else none
  std::optional<int> tag_id;
  std::vector<std::string> overrides;
};

constexpr std::array<HandDirection, 11> kDirections = {
    HandDirection::kHold,     HandDirection::kRight, HandDirection::kUpRight,  HandDirection::kUp,
    HandDirection::kUpLeft,   HandDirection::kLeft,  HandDirection::kDownLeft, HandDirection::kDown,
    HandDirection::kDownRight, HandDirection::kForward, HandDirection::kBackward};
constexpr std::array<const char*, 4> kCases = {"I", "II", "III", "none"};

std::string num(double v) { return fmt::format("{:.6g}", v); }

// What the ground truth says about one frame.
struct FrameTruth {
  bool in_view = false;     // the four corners of the black square project into the image, facing the camera
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  bool centre_projects = false;
  Vec3 P_H = Vec3::Zero();  // the tag's centre in H
  double distance_m = 0.0;  // camera to the tag's centre
};

FrameTruth frame_truth(const io::TargetGroundTruth& target, const SE3& T_W_B, const SE3& T_B_C, const SE3& T_H_C,
                       const CameraModel& camera) {
  FrameTruth t;
  const SE3 T_W_C = T_W_B * T_B_C;
  const SE3 T_C_W = T_W_C.inverse();
  const Vec3 c_C = T_C_W * target.T_W_tag.t;
  t.P_H = T_H_C * c_C;
  t.distance_m = c_C.norm();
  if (const auto px = camera.project(c_C)) {
    t.centre_px = *px;
    t.centre_projects = camera.in_image(*px);
  }
  // Facing: the camera is on the printed side (the tag's z points into the face).
  const Vec3 z_W = target.T_W_tag.rotation().col(2);
  if (z_W.dot(T_W_C.t - target.T_W_tag.t) >= 0.0) return t;
  const double h = 0.5 * target.tag_size_m;
  t.in_view = true;
  for (const auto& corner : {Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(h, h, 0), Vec3(-h, h, 0)}) {
    const auto px = camera.project(T_C_W * (target.T_W_tag * corner));
    if (!px || !camera.in_image(*px)) t.in_view = false;
  }
  return t;
}

struct Stats {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  nlohmann::ordered_json json() const {
    nlohmann::ordered_json j;
    j["n"] = values.size();
    if (values.empty()) return j;
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    j["median"] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    j["p90"] = v[std::min(n - 1, static_cast<std::size_t>(std::ceil(0.9 * static_cast<double>(n))) - 1)];
    j["max"] = v.back();
    return j;
  }
};

void run(const HandGuideArgs& a) {
  if (a.recording.empty()) throw UsageError("--recording is required");
  if (a.out.empty()) throw UsageError("--out is required");
  std::string poses_kind = a.poses;
  if (poses_kind.empty()) poses_kind = a.estimate.empty() ? "none" : "estimate";
  if (poses_kind == "estimate" && a.estimate.empty()) throw UsageError("--poses estimate needs --estimate RUN_DIR");
  if (poses_kind != "estimate" && !a.estimate.empty())
    throw UsageError("--estimate is given but --poses is '" + poses_kind + "'");

  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", a.overrides)
                                              : Config::load(a.config_file, a.overrides);
  const ConfigReads reads(config);
  planning::AprilTagDetectorConfig detector_config = planning::read_apriltag_detector_config(config);
  const planning::HandGuidanceConfig guidance_config = planning::read_hand_guidance_config(config);
  const std::vector<double> t_H_C = get(config, runtime::hand_camera_translation_key());
  config.reject_unknown_keys(ConfigSchema()
                                 .add(planning::apriltag_detector_config_schema())
                                 .add(planning::hand_guidance_config_schema())
                                 .add(runtime::hand_camera_translation_key()));
  const SE3 T_H_C(Quat::Identity(), Vec3(t_H_C[0], t_H_C[1], t_H_C[2]));

  const io::Recording recording = read_camera_recording(a.recording, "camera images");
  if (recording.calibration.cameras.empty()) throw Error(a.recording.string() + ": no camera in the calibration");
  const CameraCalibration& calib = recording.calibration.cameras.front();
  std::vector<RgbdFrame> frames;
  for (const auto& f : recording.frames)
    if (f.camera == calib.name && !f.intensity_path.empty()) frames.push_back(f);
  if (frames.empty())
    throw Error(a.recording.string() + ": no intensity images of camera '" + calib.name +
                "' (a feature-level recording has no images to find the tag in)");
  const std::unique_ptr<CameraModel> camera = make_camera_model(calib, a.recording.string());

  // The target: from --tag-id, else the recording's ground truth (targets.csv).
  std::vector<io::TargetGroundTruth> targets;
  const fs::path targets_file = a.recording / io::kTargetsCsv;
  if (fs::exists(targets_file)) targets = io::read_targets_csv(targets_file);
  const simulation::AprilTagFamilyInfo family = simulation::apriltag_family_info(detector_config.family);
  int tag_id = 0;
  if (a.tag_id) {
    tag_id = *a.tag_id;
    if (tag_id < 0 || tag_id >= family.ncodes)
      throw UsageError(fmt::format("--tag-id {} is not a tag of family {} (0 .. {})", tag_id, detector_config.family,
                                   family.ncodes - 1));
  } else {
    const auto it = std::find_if(targets.begin(), targets.end(),
                                 [&](const io::TargetGroundTruth& t) { return t.tag_family == detector_config.family; });
    if (it == targets.end())
      throw UsageError("--tag-id is required: " + a.recording.string() + " has no targets.csv with a " +
                       detector_config.family + " tag");
    tag_id = it->tag_id;
  }
  std::optional<io::TargetGroundTruth> truth_target;
  for (const auto& t : targets)
    if (t.tag_id == tag_id && t.tag_family == detector_config.family) truth_target = t;

  FramePoses poses(frames.size());
  if (poses_kind == "estimate") {
    const fs::path estimates_file = a.estimate / "estimates.csv";
    poses = poses_from_estimates(frames, experiments::read_estimates_csv(estimates_file), estimates_file);
  } else if (poses_kind == "groundtruth") {
    poses = poses_from_groundtruth(recording, frames, calib.time_offset_s);
  }
  FramePoses truth_poses(frames.size());
  const bool has_truth = truth_target && !recording.groundtruth.empty();
  if (has_truth) truth_poses = poses_from_groundtruth(recording, frames, calib.time_offset_s);

  planning::AprilTagDetector detector(detector_config);
  planning::HandGuidance guidance(guidance_config, *camera, T_H_C);
  const double depth_min = calib.depth_max_m > 0.0 ? calib.depth_min_m : 0.3;
  const double depth_max = calib.depth_max_m > 0.0 ? calib.depth_max_m : 5.0;

  fs::create_directories(a.out);
  const fs::path csv_path = a.out / "guidance.csv";
  std::ofstream csv(csv_path);
  if (!csv) throw IoError(csv_path.string(), "cannot write");
  csv << "t_ns,case,hand,reason,action,confidence,target_hx,target_hy,target_hz,heading_deg,detected,tag_u,tag_v,"
         "depth_valid,depth_total,pose,true_in_view,true_u,true_v,true_hx,true_hy,true_hz,detail\n";

  std::vector<interaction::GuidanceTimelineEntry> timeline;  // every command, for navaid cues
  std::map<std::string, std::size_t> per_case, per_direction, per_reason;
  std::size_t detected_frames = 0, in_view = 0, detected_in_view = 0, detected_out_of_view = 0;
  std::optional<std::size_t> first_seen;
  Stats centre_error_px;
  std::map<std::string, Stats> target_error_m;  // per case
  constexpr std::array<double, 5> kBins = {2.0, 3.0, 4.0, 5.0, 1e9};
  std::array<std::size_t, kBins.size()> bin_in_view{}, bin_detected{};
  std::optional<Vec3> last_remembered_W;
  Progress progress("hand guidance", frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    progress.update(i);
    const RgbdFrame& frame = frames[i];
    const std::optional<runtime::TagTarget> seen = runtime::detect_tag_target(
        frame, detector, camera.get(), {tag_id, guidance_config.patch_half_px, depth_min, depth_max});
    std::optional<planning::TargetDetection> detection;
    if (seen) detection = seen->target;
    StateEstimate estimate;
    if (poses[i]) {
      estimate = *poses[i];
    } else {
      estimate.mode = EstimatorMode::kInitializing;  // no pose: cases I and II only
    }
    estimate.t = frame.t;
    const bool had_remembered = guidance.remembered().has_value();
    GuidanceCommand cmd;
    try {
      cmd = guidance.update(estimate, detection);
    } catch (const IoError&) {
      throw;
    } catch (const Error& e) {
      throw Error(fmt::format("frame {} (t = {} ns): {}", frame.index, frame.t, e.what()));
    }
    std::string kase = "none";
    if (detection) {
      kase = (cmd.reason == GuidanceReason::kTargetFar) ? "II" : "I";
    } else if (had_remembered) {
      kase = "III";
    }
    if (guidance.remembered()) last_remembered_W = guidance.remembered()->P_W;
    ++per_case[kase];
    ++per_reason[std::string(planning::to_string(cmd.reason))];
    const std::string hand = cmd.hand ? std::string(planning::to_string(*cmd.hand)) : std::string("none");
    ++per_direction[hand];
    if (detection) {
      ++detected_frames;
      if (!first_seen) first_seen = i;
    }

    FrameTruth truth;
    const bool truth_here = has_truth && truth_poses[i].has_value();
    if (truth_here) {
      truth = frame_truth(*truth_target, truth_poses[i]->T_W_B, calib.T_B_C, T_H_C, *camera);
      if (truth.in_view) {
        ++in_view;
        const std::size_t bin = static_cast<std::size_t>(
            std::find_if(kBins.begin(), kBins.end(), [&](double b) { return truth.distance_m < b; }) - kBins.begin());
        ++bin_in_view[bin];
        if (detection) {
          ++detected_in_view;
          ++bin_detected[bin];
        }
      } else if (detection) {
        ++detected_out_of_view;
      }
      if (detection && truth.centre_projects) centre_error_px.add((seen->tag.centre_px - truth.centre_px).norm());
      if (cmd.target_H) target_error_m[kase].add((*cmd.target_H - truth.P_H).norm());
    }

    const auto& d = detection && detection->depth ? detection->depth : std::optional<planning::DepthPatchStats>{};
    std::string row = fmt::format("{},{},{},{},{},{}", frame.t, kase, hand, planning::to_string(cmd.reason),
                                  planning::to_string(cmd.action), num(cmd.confidence));
    row += cmd.target_H ? fmt::format(",{},{},{}", num(cmd.target_H->x()), num(cmd.target_H->y()), num(cmd.target_H->z()))
                        : std::string(",,,");
    row += "," + (cmd.heading_rad ? num(planning::rad_to_deg(*cmd.heading_rad)) : std::string());
    row += fmt::format(",{},{},{}", detection ? 1 : 0, seen ? num(seen->tag.centre_px.x()) : "",
                       seen ? num(seen->tag.centre_px.y()) : "");
    row += fmt::format(",{},{}", d ? std::to_string(d->valid) : "", d ? std::to_string(d->total) : "");
    row += fmt::format(",{}", poses[i] ? to_string(poses[i]->mode) : std::string_view("none"));
    if (truth_here) {
      row += fmt::format(",{},{},{},{},{},{}", truth.in_view ? 1 : 0, truth.centre_projects ? num(truth.centre_px.x()) : "",
                         truth.centre_projects ? num(truth.centre_px.y()) : "", num(truth.P_H.x()), num(truth.P_H.y()),
                         num(truth.P_H.z()));
    } else {
      row += ",,,,,,";
    }
    row += "," + csv_field(cmd.detail) + "\n";
    csv << row;
    timeline.emplace_back(cmd);
  }
  progress.finish();
  interaction::write_guidance_timeline_csv(a.out / "guidance_timeline.csv", timeline);
  csv.close();
  if (!csv) throw IoError(csv_path.string(), "cannot write");

  nlohmann::ordered_json s;
  s["recording"] = fs::absolute(a.recording).string();
  s["poses"] = poses_kind == "estimate" ? fs::absolute(a.estimate / "estimates.csv").string() : poses_kind;
  s["tag_family"] = detector_config.family;
  s["tag_id"] = tag_id;
  s["frames"] = frames.size();
  s["frames_with_detection"] = detected_frames;
  if (first_seen) {
    s["first_seen"] = {{"frame", frames[*first_seen].index}, {"t_ns", frames[*first_seen].t},
                       {"seconds_from_start", ns_to_seconds(frames[*first_seen].t - frames.front().t)}};
  } else {
    s["first_seen"] = nullptr;
  }
  for (const char* c : kCases) s["cases"][c] = per_case[c];
  for (const HandDirection dir : kDirections) {
    const std::string name(planning::to_string(dir));
    s["hand_directions"][name] = per_direction[name];
  }
  s["hand_directions"]["none"] = per_direction["none"];
  for (const auto& [reason, n] : per_reason) s["reasons"][reason] = n;
  if (last_remembered_W) s["remembered_P_W"] = {last_remembered_W->x(), last_remembered_W->y(), last_remembered_W->z()};
  if (has_truth) {
    auto& t = s["ground_truth"];
    t["target"] = truth_target->name;
    t["tag_centre_W"] = {truth_target->T_W_tag.t.x(), truth_target->T_W_tag.t.y(), truth_target->T_W_tag.t.z()};
    t["frames_in_view"] = in_view;
    t["detected_in_view"] = detected_in_view;
    t["detection_rate_in_view"] = in_view > 0 ? static_cast<double>(detected_in_view) / static_cast<double>(in_view) : 0.0;
    t["detected_out_of_view"] = detected_out_of_view;
    auto& bins = t["in_view_by_distance"];
    for (std::size_t b = 0; b < kBins.size(); ++b) {
      const std::string label = b == 0                   ? fmt::format("0-{}m", kBins[b])
                                : b + 1 < kBins.size() ? fmt::format("{}-{}m", kBins[b - 1], kBins[b])
                                                       : fmt::format(">={}m", kBins[b - 1]);
      bins[label] = {{"in_view", bin_in_view[b]}, {"detected", bin_detected[b]}};
    }
    t["centre_error_px"] = centre_error_px.json();
    for (const char* c : kCases)
      if (target_error_m.count(c)) t["target_H_error_m"][c] = target_error_m[c].json();
    if (last_remembered_W && poses_kind == "groundtruth")
      t["remembered_error_m"] = (*last_remembered_W - truth_target->T_W_tag.t).norm();
  }
  std::ofstream(a.out / "summary.json") << s.dump(2) << "\n";
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());

  std::cout << fmt::format("{} frames, tag {} {} detected in {}", frames.size(), detector_config.family, tag_id,
                           detected_frames);
  if (first_seen)
    std::cout << fmt::format(" (first seen in frame {}, {:.2f} s from the start)", frames[*first_seen].index,
                             ns_to_seconds(frames[*first_seen].t - frames.front().t));
  std::cout << "\ncases:";
  for (const char* c : kCases) std::cout << fmt::format(" {} {}", c, per_case[c]);
  std::cout << "\nhand directions:";
  for (const auto& [name, n] : per_direction)
    if (n > 0) std::cout << fmt::format(" {} {}", name, n);
  std::cout << "\n";
  if (has_truth) {
    std::cout << fmt::format("ground truth: tag in view in {} frames, detected in {} ({:.1f} %), {} detections out of view",
                             in_view, detected_in_view,
                             in_view > 0 ? 100.0 * static_cast<double>(detected_in_view) / static_cast<double>(in_view) : 0.0,
                             detected_out_of_view);
    for (const char* c : kCases)
      if (target_error_m.count(c)) {
        const auto j = target_error_m[c].json();
        std::cout << fmt::format("; case {} target_H error median {:.3f} m", c, j["median"].get<double>());
      }
    std::cout << "\n";
  }
}

}  // namespace

void add_hand_guide_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("hand-guide", "W-ROMA hand guidance to an AprilTag-marked object on every frame of a recording");
  auto a = std::make_shared<HandGuideArgs>();
  cmd->add_option("--recording", a->recording, "Recording with intensity (and depth) images");
  cmd->add_option("--estimate", a->estimate, "navaid run folder whose estimates.csv gives each frame's StateEstimate");
  cmd->add_option("--poses", a->poses,
                  "Where poses come from: estimate (--estimate), groundtruth, none (cases I and II only); default: "
                  "estimate with --estimate, else none")
      ->check(CLI::IsMember({"estimate", "groundtruth", "none"}));
  cmd->add_option("--out", a->out, "Folder to write (guidance.csv, guidance_timeline.csv, summary.json, config.yaml)");
  cmd->add_option("--tag-id", a->tag_id, "Id of the target's tag (default: the recording's targets.csv)");
  cmd->add_option("--config", a->config_file, "YAML configuration (planning.hand.*, planning.apriltag.* keys)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set planning.apriltag.quad_decimate=2 (repeatable)");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
