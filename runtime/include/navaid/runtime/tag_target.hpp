#pragma once
// The tagged object in one camera frame, as the hand unit sees it: the frame's intensity and
// depth loaded, the AprilTag of the wanted id found, and its target read from the depth around
// it. One place for the W-ROMA device's stage and `navaid hand-guide`.
#include <optional>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/hand_guidance.hpp"

namespace navaid::runtime {

struct TagTargetOptions {
  int tag_id = 0;
  int patch_half_px = 5;  ///< half size of the depth patch around the tag's centre
  double depth_min_m = 0.3, depth_max_m = 5.0;  ///< the depth sensor's valid range
};

/// The tag as the detector found it and the target read from the depth around it.
struct TagTarget {
  planning::AprilTagDetection tag;
  planning::TargetDetection target;
};

/// Tag `options.tag_id` in `frame` (its images are loaded here; labels are not), nullopt when it
/// is not in view. Throws IoError when the frame's images cannot be read.
std::optional<TagTarget> detect_tag_target(RgbdFrame frame, planning::AprilTagDetector& detector,
                                           const CameraModel* camera, const TagTargetOptions& options);

}  // namespace navaid::runtime
