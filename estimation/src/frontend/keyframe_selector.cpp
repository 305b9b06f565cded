#include "navaid/estimation/frontend/keyframe_selector.hpp"

#include <stdexcept>
#include <string>

namespace navaid::estimation {
namespace {

void require_sorted(const FeatureFrame& f, const char* which) {
  for (std::size_t i = 1; i < f.features.size(); ++i)
    if (f.features[i].track_id <= f.features[i - 1].track_id)
      throw std::invalid_argument(std::string("decide_keyframe: track ids of the ") + which +
                                  " frame are not strictly increasing");
}

}  // namespace

KeyframeDecision decide_keyframe(const FeatureFrame& last_keyframe, const FeatureFrame& current, const CameraModel& camera,
                                 const KeyframeCriteria& criteria, const std::optional<Eigen::Matrix3d>& R_cur_kf) {
  require_sorted(last_keyframe, "keyframe");
  require_sorted(current, "current");
  const Eigen::Vector2d f(camera.fx(), camera.fy());
  KeyframeDecision d;
  double sum = 0.0;
  // Both lists are sorted by id: one merge pass finds the common tracks.
  auto a = last_keyframe.features.begin();
  auto b = current.features.begin();
  while (a != last_keyframe.features.end() && b != current.features.end()) {
    if (a->track_id < b->track_id) {
      ++a;
    } else if (b->track_id < a->track_id) {
      ++b;
    } else {
      std::optional<Vec3> ray_kf = camera.unproject(a->uv);
      const std::optional<Vec3> ray_cur = camera.unproject(b->uv);
      if (ray_kf && ray_cur) {
        if (R_cur_kf) *ray_kf = *R_cur_kf * *ray_kf;
        if (ray_kf->z() > CameraModel::kMinDepth) {
          const Eigen::Vector2d n_kf = ray_kf->head<2>() / ray_kf->z();
          const Eigen::Vector2d n_cur = ray_cur->head<2>() / ray_cur->z();
          sum += (n_cur - n_kf).cwiseProduct(f).norm();
          ++d.common_tracks;
        }
      }
      ++a;
      ++b;
    }
  }
  d.average_parallax_px = d.common_tracks > 0 ? sum / static_cast<double>(d.common_tracks) : 0.0;
  d.keyframe = d.common_tracks < criteria.min_tracked || d.average_parallax_px >= criteria.min_parallax_px;
  return d;
}

}  // namespace navaid::estimation
