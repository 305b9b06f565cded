#include "navaid/mapping/semantic_point_cloud.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {
const SemanticPointCloudConfig kSemanticPointCloudDefaults;
const ConfigKey<int> kPixelStride{"mapping.cloud.pixel_stride", kSemanticPointCloudDefaults.pixel_stride, 1, 64,
                                  "map every n-th pixel in u and v"};
const ConfigKey<double> kDepthMin{"mapping.cloud.depth_min_m", kSemanticPointCloudDefaults.depth_min_m, {0.0, 100.0},
                                  "nearer depths are sensor artefacts [m]"};
const ConfigKey<double> kDepthMax{"mapping.cloud.depth_max_m", kSemanticPointCloudDefaults.depth_max_m, {0.01, 100.0},
                                  "farther depths are too noisy to map [m] (> depth_min_m)"};
const ConfigKey<std::vector<std::string>> kIgnoredClasses{"mapping.cloud.ignored_classes", {"sky"},
                                                          "semantic classes whose points are dropped, e.g. [sky, person]"};
const ConfigKey<double> kDefaultLabelProbability{"mapping.cloud.default_label_probability",
                                                 kSemanticPointCloudDefaults.default_label_probability, {0.0, 1.0},
                                                 "class probability of a labelled pixel without a confidence image"};
}  // namespace

ConfigSchema semantic_point_cloud_config_schema() {
  return ConfigSchema().add(kPixelStride).add(kDepthMin).add(kDepthMax).add(kIgnoredClasses).add(kDefaultLabelProbability);
}

SemanticPointCloudConfig read_semantic_point_cloud_config(const Config& c) {
  SemanticPointCloudConfig out;
  out.pixel_stride = get(c, kPixelStride);
  out.depth_min_m = get(c, kDepthMin);
  out.depth_max_m = get(c, kDepthMax);
  if (out.depth_max_m <= out.depth_min_m)
    throw ConfigError(c.origin("mapping.cloud.depth_max_m"), "mapping.cloud.depth_max_m",
                      "must exceed mapping.cloud.depth_min_m (" + std::to_string(out.depth_min_m) + ")");
  const auto names = get(c, kIgnoredClasses);
  out.ignored_classes.clear();
  for (const auto& name : names) {
    try {
      out.ignored_classes.push_back(semantic_class_from_name(name));
    } catch (const ConfigError& e) {
      throw ConfigError(c.origin("mapping.cloud.ignored_classes"), "mapping.cloud.ignored_classes", e.what());
    }
  }
  out.default_label_probability = get(c, kDefaultLabelProbability);
  return out;
}

namespace {

template <typename T>
void check_same_size(const Image<T>& image, const ImageF32& depth, const char* what, const RgbdFrame& frame) {
  if (image.width != depth.width || image.height != depth.height)
    throw Error("frame " + std::to_string(frame.index) + ": " + what + " image is " + std::to_string(image.width) +
                "x" + std::to_string(image.height) + ", depth is " + std::to_string(depth.width) + "x" +
                std::to_string(depth.height));
}

}  // namespace

SemanticPointCloud make_semantic_point_cloud(const RgbdFrame& frame, const CameraCalibration& camera,
                                             const SE3& T_W_B, const SemanticPointCloudConfig& config) {
  const ImageF32& depth = frame.depth;
  if (depth.empty()) throw Error("frame " + std::to_string(frame.index) + ": no depth image loaded");
  if (depth.width != camera.width || depth.height != camera.height)
    throw Error((frame.depth_path.empty() ? std::string() : frame.depth_path + ": ") + "frame " +
                std::to_string(frame.index) + ": depth is " + std::to_string(depth.width) + "x" +
                std::to_string(depth.height) + ", camera " + camera.name + " is " + std::to_string(camera.width) +
                "x" + std::to_string(camera.height));
  const ImageU8* labels = frame.labels ? &*frame.labels : nullptr;
  const ImageF32* confidence = frame.label_confidence ? &*frame.label_confidence : nullptr;
  if (labels) check_same_size(*labels, depth, "label", frame);
  if (confidence) check_same_size(*confidence, depth, "confidence", frame);

  std::array<bool, kNumSemanticClasses> ignored{};
  for (const auto c : config.ignored_classes) ignored[static_cast<std::size_t>(c)] = true;

  const SE3 T_W_C = T_W_B * camera.T_B_C;
  const Eigen::Matrix3f R = T_W_C.q.toRotationMatrix().cast<float>();
  const Eigen::Vector3f t = T_W_C.t.cast<float>();

  // A distorted lens: unproject every sampled pixel once through the camera model.
  std::unique_ptr<CameraModel> model;
  if (camera.distortion != DistortionModel::kNone) model = make_camera_model(camera);

  SemanticPointCloud cloud;
  cloud.origin_W = T_W_C.t;
  cloud.labelled = labels != nullptr;
  const int stride = config.pixel_stride;
  cloud.points.reserve(static_cast<std::size_t>((depth.width + stride - 1) / stride) *
                       static_cast<std::size_t>((depth.height + stride - 1) / stride));
  const float inv_fx = static_cast<float>(1.0 / camera.fx), inv_fy = static_cast<float>(1.0 / camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  const float dmin = static_cast<float>(config.depth_min_m), dmax = static_cast<float>(config.depth_max_m);
  const float default_p = static_cast<float>(config.default_label_probability);

  for (int v = 0; v < depth.height; v += stride) {
    for (int u = 0; u < depth.width; u += stride) {
      const float d = depth.at(u, v);
      if (!std::isfinite(d) || d <= 0.0f) {
        ++cloud.invalid_depth;
        continue;
      }
      if (d < dmin || d > dmax) {
        ++cloud.out_of_range;
        continue;
      }
      SemanticObservation obs;
      if (labels) {
        const std::uint8_t id = labels->at(u, v);
        if (!is_valid_semantic_id(id))
          throw Error((frame.labels_path.empty() ? std::string() : frame.labels_path + ": ") + "frame " +
                      std::to_string(frame.index) + ": label " + std::to_string(id) + " at pixel (" +
                      std::to_string(u) + ", " + std::to_string(v) + ") is not a class id (0.." +
                      std::to_string(kNumSemanticClasses - 1) + ")");
        if (ignored[id]) {
          ++cloud.ignored_class;
          continue;
        }
        obs.semantic = static_cast<SemanticClass>(id);
        obs.probability = confidence ? std::clamp(confidence->at(u, v), 0.0f, 1.0f) : default_p;
        if (obs.semantic == SemanticClass::kUnlabeled) obs.probability = 0.0f;
      }
      Eigen::Vector3f p_C;
      if (model) {
        const auto bearing = model->unproject(CameraModel::Vec2(u, v));
        if (!bearing) {
          ++cloud.not_unprojected;
          continue;
        }
        p_C = (*bearing * (static_cast<double>(d) / bearing->z())).cast<float>();
      } else {
        p_C = Eigen::Vector3f((static_cast<float>(u) - cx) * d * inv_fx, (static_cast<float>(v) - cy) * d * inv_fy, d);
      }
      cloud.points.push_back({R * p_C + t, obs});
    }
  }
  return cloud;
}

}  // namespace navaid::mapping
