// W-ROMA's chain (seed w-roma, §IV): the AprilTag detector on each frame's intensity image, the
// depth patch around the tag's centre, and hand guidance with the frame's estimate (cases I / II /
// III: detected with depth, detected beyond the depth range, remembered through the pose). The
// target's tag: device.tag_id, else the mission's.
#include <fmt/format.h>

#include <array>
#include <map>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/runtime/guidance_stage.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/runtime/tag_target.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/hand_guidance.hpp"

namespace navaid::runtime {
namespace {

const ConfigKey<int> kTagId{"device.tag_id", std::nullopt, 0, 586,
                            "hand-target guidance: the object's tag; absent: the mission's (a recording's targets.csv)"};

int target_tag_id(const GuidanceStageContext& c, const std::string& family) {
  if (c.config.has(kTagId.name)) return get(c.config, kTagId);
  if (c.mission.tag_id) return *c.mission.tag_id;
  throw Error("device " + c.spec.name + " guides the hand to a tagged object: set device.tag_id (the " + family +
              " tag on the object)");
}

SE3 hand_from_camera(const Config& config) {
  const std::vector<double> t = get(config, hand_camera_translation_key());
  return SE3(Quat::Identity(), Vec3(t[0], t[1], t[2]));
}

}  // namespace

ConfigSchema hand_target_stage_schema() {
  return ConfigSchema()
      .add(kTagId)
      .add(hand_camera_translation_key())
      .add(planning::apriltag_detector_config_schema())
      .add(planning::hand_guidance_config_schema());
}

namespace {

class HandTargetStage final : public GuidanceStage {
 public:
  explicit HandTargetStage(const GuidanceStageContext& c)
      : detector_config_(planning::read_apriltag_detector_config(c.config)),
        guidance_config_(planning::read_hand_guidance_config(c.config)),
        tag_id_(target_tag_id(c, detector_config_.family)),
        camera_(make_camera_model(c.camera, "device " + c.spec.name)),
        detector_(detector_config_),
        guidance_(guidance_config_, *camera_, hand_from_camera(c.config)),
        depth_min_m_(c.camera.depth_max_m > 0.0 ? c.camera.depth_min_m : 0.3),
        depth_max_m_(c.camera.depth_max_m > 0.0 ? c.camera.depth_max_m : 5.0) {}

  GuidanceOutput update(const GuidanceInput& in) override {
    GuidanceOutput out;
    out.planner = "hand-guidance";
    const std::optional<TagTarget> seen = detect_tag_target(
        in.frame, detector_, camera_.get(), {tag_id_, guidance_config_.patch_half_px, depth_min_m_, depth_max_m_});
    std::optional<planning::TargetDetection> detection;
    if (seen) {
      ++detected_;
      detection = seen->target;
    }
    out.command = guidance_.update(in.estimate, detection);
    ++reasons_[std::string(planning::to_string(out.command.reason))];
    return out;
  }

  nlohmann::ordered_json summary() const override {
    nlohmann::ordered_json r = nlohmann::ordered_json::object();
    for (const auto& [name, n] : reasons_) r[name] = n;
    return {{"tag_family", detector_config_.family}, {"tag_id", tag_id_}, {"frames_detected", detected_}, {"reasons", r}};
  }

 private:
  planning::AprilTagDetectorConfig detector_config_;
  planning::HandGuidanceConfig guidance_config_;
  int tag_id_;
  std::unique_ptr<CameraModel> camera_;
  planning::AprilTagDetector detector_;
  planning::HandGuidance guidance_;
  double depth_min_m_, depth_max_m_;
  std::size_t detected_ = 0;
  std::map<std::string, std::size_t> reasons_;
};

}  // namespace

std::unique_ptr<GuidanceStage> make_hand_target_stage(const GuidanceStageContext& context) {
  return std::make_unique<HandTargetStage>(context);
}

}  // namespace navaid::runtime
