// The augmented-cane obstacle pipeline on PCL (thesis Ch. 2.2.2, App. D.2); see
// obstacle_pipeline.hpp for the stages and docs/mapping.md ("Obstacle pipeline") for the choices.
#include "navaid/mapping/obstacle_pipeline.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <unordered_set>

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>
#include <pcl/filters/approximate_voxel_grid.h>
#include <pcl/filters/conditional_removal.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/sample_consensus/sac_model_plane.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "obstacle_ground_average.hpp"

namespace navaid::mapping {
namespace {

using PointT = pcl::PointXYZ;
using Cloud = pcl::PointCloud<PointT>;

struct PlaneFit {
  GroundPlane plane;
  pcl::PointIndices::Ptr inliers;
};

void set_unorganized(Cloud& c) {
  c.width = static_cast<std::uint32_t>(c.size());
  c.height = 1;
  c.is_dense = true;
}

// RANSAC on a plane whose normal is within eps of `up_C` (SACMODEL_PERPENDICULAR_PLANE: the plane
// is perpendicular to the axis). nullopt when no plane with enough inliers exists.
// Every k-th of `candidates` (all points when null), at most `max` of them: RANSAC's cost is
// iterations x points, and a few thousand points fix a plane as well as a hundred thousand.
pcl::IndicesPtr spread_sample(const pcl::IndicesPtr& candidates, std::size_t size, std::size_t max) {
  const std::size_t n = candidates ? candidates->size() : size;
  const std::size_t step = std::max<std::size_t>(1, (n + max - 1) / max);
  pcl::IndicesPtr sample(new pcl::Indices);
  sample->reserve(n / step + 1);
  for (std::size_t k = 0; k < n; k += step) sample->push_back(candidates ? (*candidates)[k] : static_cast<int>(k));
  return sample;
}

pcl::PointIndices::Ptr points_near(const Cloud::Ptr& cloud, const GroundPlane& plane, double threshold);

// RANSAC on a plane whose normal is within eps of `up_C` (SACMODEL_PERPENDICULAR_PLANE: the plane
// is perpendicular to the axis), fitted on a spread sample of `subset` (all points when null).
// The inliers are all points of `cloud` within the threshold. nullopt when no plane with enough
// inliers exists.
std::optional<PlaneFit> fit_ground(const Cloud::Ptr& cloud, const pcl::IndicesPtr& subset, const Eigen::Vector3d& up_C,
                                   const ObstaclePipelineConfig& c) {
  // Fewer points than inliers needed: RANSAC cannot succeed (and PCL would log an error).
  const std::size_t available = subset ? subset->size() : cloud->size();
  if (available < static_cast<std::size_t>(std::max(3, c.ransac_min_inliers))) return std::nullopt;
  pcl::SACSegmentation<PointT> seg;
  seg.setOptimizeCoefficients(c.ransac_optimize_coefficients);
  seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setMaxIterations(c.ransac_max_iterations);
  seg.setDistanceThreshold(c.ransac_distance_threshold_m);
  seg.setAxis(up_C.cast<float>());
  seg.setEpsAngle(c.ransac_eps_angle_rad);
  seg.setInputCloud(cloud);
  seg.setIndices(spread_sample(subset, cloud->size(), static_cast<std::size_t>(c.ransac_max_points)));
  pcl::PointIndices sample_inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(sample_inliers, coefficients);
  if (coefficients.values.size() != 4 || sample_inliers.indices.size() < 3) return std::nullopt;
  Eigen::Vector3d n(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
  double d = coefficients.values[3];
  const double norm = n.norm();
  if (!(norm > 0.0) || !std::isfinite(d)) return std::nullopt;
  // PCL's normal has either sign: make it point up so that the offset is the camera's height.
  const double sign = n.dot(up_C) < 0.0 ? -1.0 : 1.0;
  PlaneFit fit;
  fit.plane.normal_C = sign * n / norm;
  fit.plane.offset_m = sign * d / norm;
  fit.inliers = points_near(cloud, fit.plane, c.ransac_distance_threshold_m);
  if (fit.inliers->indices.size() < static_cast<std::size_t>(c.ransac_min_inliers)) return std::nullopt;
  return fit;
}

// How near the user a level starts: the 5th percentile of its inliers' horizontal distance from
// the camera (robust to a few stray inliers).
double near_range(const Cloud& cloud, const PlaneFit& fit) {
  std::vector<double> r;
  r.reserve(fit.inliers->indices.size());
  for (int i : fit.inliers->indices) {
    const Eigen::Vector3d p = cloud[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
    r.push_back((p - fit.plane.normal_C.dot(p) * fit.plane.normal_C).norm());
  }
  const auto k = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 20);
  std::nth_element(r.begin(), k, r.end());
  return *k;
}

// True when the inliers cover an area rather than a line: a horizontal band through a wall or a
// box side holds many inliers but only a strip in plan view. In 10 cm cells of the plane, a real
// level has cells whose four neighbours are all occupied; a strip has none.
bool covers_area(const Cloud& cloud, const PlaneFit& fit) {
  constexpr double kCell = 0.1;
  constexpr std::size_t kMinInteriorCells = 10;
  const Eigen::Vector3d& n = fit.plane.normal_C;
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  // Shifted as unsigned: shifting a negative cell index is undefined (found by UBSan).
  auto key = [](long long u, long long v) {
    return static_cast<long long>((static_cast<unsigned long long>(u) << 32) ^ (static_cast<unsigned long long>(v) & 0xffffffffULL));
  };
  std::unordered_set<long long> cells;
  for (int i : fit.inliers->indices) {
    const Eigen::Vector3d p = cloud[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
    cells.insert(key(std::llround(std::floor(e1.dot(p) / kCell)), std::llround(std::floor(e2.dot(p) / kCell))));
  }
  std::size_t interior = 0;
  for (long long c : cells) {
    const long long u = c >> 32, v = static_cast<long long>(static_cast<std::int32_t>(c & 0xffffffffLL));
    interior += cells.count(key(u + 1, v)) && cells.count(key(u - 1, v)) && cells.count(key(u, v + 1)) &&
                cells.count(key(u, v - 1));
    if (interior >= kMinInteriorCells) return true;
  }
  return false;
}

pcl::IndicesPtr complement(const pcl::PointIndices& inliers, std::size_t size) {
  std::vector<bool> in(size, false);
  for (int i : inliers.indices) in[static_cast<std::size_t>(i)] = true;
  pcl::IndicesPtr rest(new pcl::Indices);
  rest->reserve(size - inliers.indices.size());
  for (std::size_t i = 0; i < size; ++i)
    if (!in[i]) rest->push_back(static_cast<int>(i));
  return rest;
}

Eigen::VectorXf coefficients_of(const GroundPlane& plane) {
  Eigen::VectorXf c(4);
  c << plane.normal_C.cast<float>(), static_cast<float>(plane.offset_m);
  return c;
}

// Least-squares refits on the points within `threshold` of the plane, a few times: the plane
// moves off wall bases and low clutter that the wide band let in, but stays a single-level fit.
GroundPlane tighten(const Cloud::Ptr& cloud, GroundPlane plane, double threshold) {
  pcl::SampleConsensusModelPlane<PointT> model(cloud);
  for (int k = 0; k < 3; ++k) {
    const pcl::PointIndices::Ptr near = points_near(cloud, plane, threshold);
    if (near->indices.size() < 3) break;
    Eigen::VectorXf refined;
    model.optimizeModelCoefficients(near->indices, coefficients_of(plane), refined);
    Eigen::Vector3d n = refined.head<3>().cast<double>();
    const double norm = n.norm();
    if (!(norm > 0.0)) break;
    const double sign = n.dot(plane.normal_C) < 0.0 ? -1.0 : 1.0;
    plane.normal_C = sign * n / norm;
    plane.offset_m = sign * refined[3] / norm;
  }
  return plane;
}

// The points within `threshold` of the plane. A plain loop: PCL's selectWithinDistance also
// stores every distance and was a third of the frame time.
pcl::PointIndices::Ptr points_near(const Cloud::Ptr& cloud, const GroundPlane& plane, double threshold) {
  pcl::PointIndices::Ptr inliers(new pcl::PointIndices);
  const Eigen::Vector3f n = plane.normal_C.cast<float>();
  const auto d = static_cast<float>(plane.offset_m), t = static_cast<float>(threshold);
  const std::size_t size = cloud->size();
  for (std::size_t i = 0; i < size; ++i)
    if (std::abs(n.dot((*cloud)[i].getVector3fMap()) + d) <= t) inliers->indices.push_back(static_cast<int>(i));
  return inliers;
}

// Keeps the points no more than `height` above the plane: the thesis's ConditionalRemoval with a
// TfQuadraticXYZComparison p'Ap + 2v'p + c <= 0, A = 0, v = n / 2, c = D - height (eq. 2.4).
void remove_above(const Cloud::Ptr& in, const GroundPlane& plane, double height, Cloud& out) {
  out.clear();
  if (in->empty()) return;
  auto below = std::make_shared<pcl::ConditionAnd<PointT>>();
  below->addComparison(std::make_shared<pcl::TfQuadraticXYZComparison<PointT>>(
      pcl::ComparisonOps::LE, Eigen::Matrix3f::Zero(), Eigen::Vector3f((0.5 * plane.normal_C).cast<float>()),
      static_cast<float>(plane.offset_m - height)));
  pcl::ConditionalRemoval<PointT> removal;
  removal.setCondition(below);
  removal.setInputCloud(in);
  removal.filter(out);
}

void keep_nearest(const Eigen::Vector3f& p_U, float range, std::size_t bin, std::vector<float>& ranges,
                  std::vector<Eigen::Vector3f>& nearest) {
  if (range < ranges[bin]) {
    ranges[bin] = range;
    nearest[bin] = p_U;
  }
}

}  // namespace

struct ObstaclePipeline::Impl {
  explicit Impl(const ObstaclePipelineConfig& c) : config(c), average(c.running_average_frames) {}

  ObstaclePipelineConfig config;
  GroundAverage average;
  // Buffers reused across frames (a 640x480 frame is 300k points).
  Cloud::Ptr finite{new Cloud}, voxels{new Cloud}, non_ground{new Cloud}, kept{new Cloud};
  Cloud kept_U;

  // Level refinement. The thesis's 0.1 m band lets wall bases and kerbs pull the least-squares
  // plane: with two levels RANSAC even prefers a slightly tilted plane through both. So find the
  // dominant flat level with a tight band, then a second level parallel to it among the points
  // outside its ground band; if one covers an area and lies within the step height, the ground
  // is the level nearer to the user (the one under the user's feet). Otherwise the thesis's
  // plane stands, tightened onto the floor proper (a step within the band stays in it).
  void refine_level(PlaneFit& fit, ObstacleScanCounters& n) const {
    ObstaclePipelineConfig tight = config;
    tight.ransac_distance_threshold_m = config.level_fit_threshold_m;
    tight.ransac_eps_angle_rad = config.level_eps_angle_rad;
    const double band = config.ransac_distance_threshold_m;
    const std::optional<PlaneFit> first = fit_ground(voxels, nullptr, fit.plane.normal_C, tight);
    std::optional<PlaneFit> second;
    if (first) {
      const pcl::PointIndices::Ptr first_band = points_near(voxels, first->plane, band);
      second = fit_ground(voxels, complement(*first_band, voxels->size()), first->plane.normal_C, tight);
    }
    const double step = second ? std::abs(second->plane.offset_m - first->plane.offset_m) : 0.0;
    if (second && step > band && step <= config.max_step_height_m && covers_area(*voxels, *second)) {
      n.second_level_found = true;
      n.second_level_chosen = near_range(*voxels, *second) < near_range(*voxels, *first);
      fit.plane = n.second_level_chosen ? second->plane : first->plane;
    } else {
      fit.plane = tighten(voxels, fit.plane, config.level_fit_threshold_m);
    }
    fit.inliers = points_near(voxels, fit.plane, band);
  }

  // Picks this frame's plane (thesis "Ground Plane Filtering") and returns its ground points.
  pcl::PointIndices::Ptr choose_ground(const SE3& T_U_C_prior, ObstacleScan& scan) {
    ObstacleScanCounters& n = scan.counters;
    const GroundPlane prior = ground_plane_of(T_U_C_prior);
    std::optional<PlaneFit> fit = fit_ground(voxels, nullptr, prior.normal_C, config);
    n.ransac_succeeded = fit.has_value();
    if (fit && config.level_refinement) refine_level(*fit, n);
    if (fit && average.offset_deviation(fit->plane) <= config.running_average_max_deviation_m) {
      n.ground_source = GroundSource::kRansac;
      scan.ground = fit->plane;
      average.add(fit->plane);
      return fit->inliers;
    }
    if (!average.empty()) {
      // A horizontal surface at the wrong height (a table) or no plane at all. The thesis keeps
      // a rejected plane's normal and substitutes D_avg for D; we take the averaged normal too,
      // since a false plane may be tilted by up to the angle tolerance.
      n.ground_source = fit ? GroundSource::kRunningAverageRejected : GroundSource::kRunningAverageNoPlane;
      scan.ground = average.plane();
    } else {
      n.ground_source = GroundSource::kPrior;
      scan.ground = prior;
    }
    n.running_average_used = n.ground_source != GroundSource::kPrior;
    // A remembered plane is less exact than a fitted one: widen the inlier band.
    return points_near(voxels, scan.ground, config.fallback_distance_threshold_m);
  }

  ObstacleScan process(const std::vector<Eigen::Vector3f>& points_C, const SE3& T_U_C_prior, Timestamp t) {
    const ObstaclePipelineConfig& c = config;
    ObstacleScan scan = ObstacleScan::empty(c.scan_bins(), c.scan_min_bearing_rad, c.scan_bin_width_rad);
    scan.t = t;
    ObstacleScanCounters& n = scan.counters;
    n.points_in = points_C.size();

    // Non-finite points (no depth) would poison the voxel hash: skip and count them.
    finite->clear();
    finite->reserve(points_C.size());
    for (const Eigen::Vector3f& p : points_C) {
      if (p.allFinite())
        finite->push_back(PointT(p.x(), p.y(), p.z()));
      else
        ++n.non_finite;
    }
    set_unorganized(*finite);

    // Approximate voxel grid: hash-based approximate centroids, faster than VoxelGrid.
    voxels->clear();
    if (!finite->empty()) {
      pcl::ApproximateVoxelGrid<PointT> grid;
      const auto leaf = static_cast<float>(c.voxel_leaf_size_m);
      grid.setLeafSize(leaf, leaf, leaf);
      grid.setInputCloud(finite);
      grid.filter(*voxels);
    }
    n.after_voxel_grid = voxels->size();

    // Ground: RANSAC or the running average; remove its points.
    const pcl::PointIndices::Ptr ground = choose_ground(T_U_C_prior, scan);
    n.ground_inliers = ground->indices.size();
    non_ground->clear();
    if (!voxels->empty()) {
      pcl::ExtractIndices<PointT> extract;
      extract.setInputCloud(voxels);
      extract.setIndices(ground);
      extract.setNegative(true);
      extract.filter(*non_ground);
    }

    remove_above(non_ground, scan.ground, c.above_head_height_m, *kept);
    n.above_head_removed = non_ground->size() - kept->size();

    scan.T_U_C = c.align_to_ground_plane ? user_frame_from_ground(scan.ground, T_U_C_prior) : T_U_C_prior;
    const Eigen::Affine3f T(scan.T_U_C.matrix().cast<float>());
    pcl::transformPointCloud(*kept, kept_U, T);

    // Nearest point per bearing bin. Below the ground plane (and outside its inlier band) is a
    // drop-off, never an obstacle: a kerb stepped down must not look like a wall.
    for (std::size_t i = 0; i < kept->size(); ++i) {
      const PointT& pc = (*kept)[i];
      const Eigen::Vector3f p_U = kept_U[i].getVector3fMap();
      const bool below = scan.ground.height_above(Eigen::Vector3d(pc.x, pc.y, pc.z)) < 0.0;
      (below ? n.drop_off_points : n.obstacle_points)++;
      const std::optional<std::size_t> bin = scan.bin_of(std::atan2(p_U.y(), p_U.x()));
      if (!bin) {
        ++n.outside_scan;
        continue;
      }
      const float range = std::hypot(p_U.x(), p_U.y());
      if (below)
        keep_nearest(p_U, range, *bin, scan.drop_off_ranges, scan.drop_off_nearest_U);
      else
        keep_nearest(p_U, range, *bin, scan.ranges, scan.nearest_U);
    }
    return scan;
  }
};

ObstaclePipeline::ObstaclePipeline(const ObstaclePipelineConfig& config) {
  validate(config);
  // A frame without a ground plane is expected (the thesis' running-average fallback, counted in
  // ObstacleScan::counters): PCL's "RANSAC found no model" on stderr for each would drown the log.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  impl_ = std::make_unique<Impl>(config);
}
ObstaclePipeline::~ObstaclePipeline() = default;
ObstaclePipeline::ObstaclePipeline(ObstaclePipeline&&) noexcept = default;
ObstaclePipeline& ObstaclePipeline::operator=(ObstaclePipeline&&) noexcept = default;

ObstacleScan ObstaclePipeline::process(const std::vector<Eigen::Vector3f>& points_C, const SE3& T_U_C_prior,
                                       Timestamp t) {
  assert(T_U_C_prior.t.allFinite() && T_U_C_prior.q.coeffs().allFinite());
  return impl_->process(points_C, T_U_C_prior, t);
}

void ObstaclePipeline::reset() { impl_->average.reset(); }
std::size_t ObstaclePipeline::running_average_count() const { return impl_->average.count(); }
GroundPlane ObstaclePipeline::running_average_plane() const { return impl_->average.plane(); }
const ObstaclePipelineConfig& ObstaclePipeline::config() const { return impl_->config; }

}  // namespace navaid::mapping
