#include "navaid/runtime/tag_target.hpp"

#include "navaid/io/image_io.hpp"

namespace navaid::runtime {

std::optional<TagTarget> detect_tag_target(RgbdFrame frame, planning::AprilTagDetector& detector,
                                           const CameraModel* camera, const TagTargetOptions& options) {
  frame.labels_path.clear();
  frame.confidence_path.clear();
  io::load_frame_images(frame);
  const ImageU8 gray = io::to_gray(frame.intensity, frame.intensity_path);
  const auto tag = planning::find_tag(detector.detect(gray, camera), options.tag_id);
  if (!tag) return std::nullopt;
  return TagTarget{*tag, planning::target_from_tag(*tag, frame.depth, options.patch_half_px, options.depth_min_m,
                                                  options.depth_max_m)};
}

}  // namespace navaid::runtime
