#include "navaid/mapping/semantic_map.hpp"

#include <cmath>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/mapping/semantic_octree.hpp"
#include "flat_key_index.hpp"

namespace navaid::mapping {

namespace {
const SemanticMapConfig kSemanticMapDefaults;
const ConfigKey<double> kSemanticMapResolution{"mapping.map.resolution_m", kSemanticMapDefaults.resolution_m, {0.01, 1.0},
                                    "voxel edge of the semantic map [m]"};
const ConfigKey<std::string> kFusion{"mapping.map.fusion", std::string("max"), {"max", "bayes"},
                                     "semantic fusion: max (eLabrador) or a Bayesian class histogram"};
const ConfigKey<double> kMaxFusionDiscount{"mapping.map.max_fusion_discount", kSemanticMapDefaults.max_fusion_discount, {0.01, 1.0},
                                           "max fusion: a disagreeing label discounts the stored confidence by this"};
const ConfigKey<double> kProbHit{"mapping.map.prob_hit", kSemanticMapDefaults.prob_hit, {0.5001, 0.9999},
                                 "OctoMap sensor model: probability of a hit"};
const ConfigKey<double> kProbMiss{"mapping.map.prob_miss", kSemanticMapDefaults.prob_miss, {0.0001, 0.4999},
                                  "OctoMap sensor model: probability of a miss"};
const ConfigKey<double> kClampMin{"mapping.map.clamp_min", kSemanticMapDefaults.clamp_min, {0.0001, 0.4999},
                                  "OctoMap clamping: lowest occupancy probability"};
const ConfigKey<double> kClampMax{"mapping.map.clamp_max", kSemanticMapDefaults.clamp_max, {0.5001, 0.9999},
                                  "OctoMap clamping: highest occupancy probability"};
const ConfigKey<double> kOccupancyThreshold{"mapping.map.occupancy_threshold", kSemanticMapDefaults.occupancy_threshold, {0.01, 0.99},
                                            "a voxel is occupied above this probability"};
const ConfigKey<double> kWindowSize{"mapping.map.window_size_m", kSemanticMapDefaults.window_size_m, {1.0, 200.0},
                                    "edge of the square map window centred on the user [m]"};
const ConfigKey<double> kWindowBelow{"mapping.map.window_below_m", kSemanticMapDefaults.window_below_m, {0.0, 50.0},
                                     "the window reaches this far below the user [m]"};
const ConfigKey<double> kWindowAbove{"mapping.map.window_above_m", kSemanticMapDefaults.window_above_m, {0.0, 50.0},
                                     "the window reaches this far above the user [m]"};
const ConfigKey<double> kPruneStep{"mapping.map.prune_step_m", kSemanticMapDefaults.prune_step_m, {0.0, 100.0},
                                   "re-prune the window once its centre moved this far [m]"};
const ConfigKey<int> kMaintenanceInterval{"mapping.map.maintenance_interval", kSemanticMapDefaults.maintenance_interval, 1, 1000,
                                          "frames between refreshes of inner nodes (OctoMap prune())"};
}  // namespace

ConfigSchema semantic_map_config_schema() {
  return ConfigSchema()
      .add(kSemanticMapResolution)
      .add(kFusion)
      .add(kMaxFusionDiscount)
      .add(kProbHit)
      .add(kProbMiss)
      .add(kClampMin)
      .add(kClampMax)
      .add(kOccupancyThreshold)
      .add(kWindowSize)
      .add(kWindowBelow)
      .add(kWindowAbove)
      .add(kPruneStep)
      .add(kMaintenanceInterval);
}

SemanticMapConfig read_semantic_map_config(const Config& c) {
  SemanticMapConfig m;
  m.resolution_m = get(c, kSemanticMapResolution);
  m.fusion = get(c, kFusion) == "max" ? FusionPolicy::kMax : FusionPolicy::kBayes;
  m.max_fusion_discount = get(c, kMaxFusionDiscount);
  m.prob_hit = get(c, kProbHit);
  m.prob_miss = get(c, kProbMiss);
  m.clamp_min = get(c, kClampMin);
  m.clamp_max = get(c, kClampMax);
  m.occupancy_threshold = get(c, kOccupancyThreshold);
  m.window_size_m = get(c, kWindowSize);
  m.window_below_m = get(c, kWindowBelow);
  m.window_above_m = get(c, kWindowAbove);
  m.prune_step_m = get(c, kPruneStep);
  m.maintenance_interval = get(c, kMaintenanceInterval);
  return m;
}

// Named, not anonymous: SemanticMap::Impl holds a TreeOps (GCC warns of a member whose type has
// internal linkage once this file is compiled inside a unity batch).
namespace semantic_map_ops {

/// The operations of the map on one tree type; one implementation per fusion policy.
class TreeOps {
 public:
  virtual ~TreeOps() = default;
  virtual InsertStats insert(const SemanticPointCloud& cloud, const Vec3& window_min, const Vec3& window_max) = 0;
  virtual void maintain() = 0;
  virtual void prune_outside(const Vec3& window_min, const Vec3& window_max) = 0;
  virtual MapVoxels occupied(const Vec3& window_min, const Vec3& window_max, double threshold) const = 0;
  virtual std::optional<MapVoxel> at(const Vec3& p) const = 0;
  virtual std::size_t leaves() const = 0;
  virtual std::size_t memory() const = 0;
  virtual void write(const std::filesystem::path& file) = 0;
  virtual void write_color(const std::filesystem::path& file, double threshold) = 0;
  virtual const void* tree() const = 0;
};

octomap::point3d to_point(const Vec3& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}
Vec3 to_vec(const octomap::point3d& p) { return {p.x(), p.y(), p.z()}; }
bool inside(const octomap::point3d& p, const Vec3& lo, const Vec3& hi) {
  return p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y() && p.z() >= lo.z() && p.z() <= hi.z();
}

template <class Fusion>
class TreeOpsT final : public TreeOps {
 public:
  using Tree = SemanticOcTree<Fusion>;
  using Node = typename Tree::Node;

  explicit TreeOpsT(std::unique_ptr<Tree> tree) : tree_(std::move(tree)) {}

  InsertStats insert(const SemanticPointCloud& cloud, const Vec3& lo, const Vec3& hi) override {
    InsertStats stats;
    stats.points = cloud.points.size();
    // The window in key units: rays are cut to it without converting every cell to metres.
    octomap::OcTreeKey key_lo, key_hi;
    if (!tree_->coordToKeyChecked(to_point(lo), key_lo) || !tree_->coordToKeyChecked(to_point(hi), key_hi))
      throw Error("SemanticMap: the window leaves the OctoMap's addressable range");
    const auto in_window = [&](const octomap::OcTreeKey& k) {
      return k[0] >= key_lo[0] && k[0] <= key_hi[0] && k[1] >= key_lo[1] && k[1] <= key_hi[1] && k[2] >= key_lo[2] &&
             k[2] <= key_hi[2];
    };
    // One ray per distinct endpoint voxel, not per point: at mapping resolutions many pixels share
    // a voxel, and the rays dominate the cost. Each point still casts its class vote in order.
    endpoints_.clear();
    first_point_.clear();
    point_slot_.assign(cloud.points.size(), kNoSlot);
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
      const Eigen::Vector3f& p = cloud.points[i].p_W;
      const octomap::point3d q(p.x(), p.y(), p.z());
      octomap::OcTreeKey key;
      if (!inside(q, lo, hi) || !tree_->coordToKeyChecked(q, key)) {
        ++stats.outside_window;
        continue;
      }
      const auto [slot, added] = endpoints_.insert(FlatKeyIndex::pack(key));
      if (added) first_point_.push_back(q);
      point_slot_[i] = slot;
    }
    stats.occupied_voxels = endpoints_.size();

    const octomap::point3d origin = to_point(cloud.origin_W);
    free_.clear();
    for (const auto& end : first_point_) {
      if (!tree_->computeRayKeys(origin, end, ray_)) continue;  // origin outside the tree's range
      for (const auto& k : ray_) {
        if (!in_window(k)) continue;
        const std::uint64_t packed = FlatKeyIndex::pack(k);
        if (!endpoints_.contains(packed)) free_.insert(packed);
      }
    }
    stats.free_voxels = free_.size();
    // Lazy updates: inner nodes are refreshed in maintain(); leaves keep their addresses until then
    // (lazy updates expand but never prune), so the node pointers below stay valid.
    for (const std::uint64_t k : free_.keys()) tree_->updateNode(FlatKeyIndex::unpack(k), false, true);
    nodes_.resize(endpoints_.size());
    for (std::size_t s = 0; s < endpoints_.size(); ++s)
      nodes_[s] = tree_->updateNode(FlatKeyIndex::unpack(endpoints_.keys()[s]), true, true);
    if (cloud.labelled) {
      for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        if (point_slot_[i] != kNoSlot) tree_->fuse(nodes_[point_slot_[i]], cloud.points[i].observation);
      }
    }
    return stats;
  }

  void maintain() override {
    tree_->updateInnerOccupancy();
    tree_->prune();
  }

  void prune_outside(const Vec3& lo, const Vec3& hi) override { tree_->delete_outside(to_point(lo), to_point(hi)); }

  MapVoxels occupied(const Vec3& lo, const Vec3& hi, double threshold) const override {
    MapVoxels out;
    if (tree_->size() == 0) return out;
    // The box is clipped to the tree's extent: OctoMap's box iterator wraps its 16-bit keys for
    // corners beyond the addressable range (a window "everywhere" must not crash).
    double x0, y0, z0, x1, y1, z1;
    tree_->getMetricMin(x0, y0, z0);
    tree_->getMetricMax(x1, y1, z1);
    const Vec3 box_lo = lo.cwiseMax(Vec3(x0, y0, z0));
    const Vec3 box_hi = hi.cwiseMin(Vec3(x1, y1, z1));
    if ((box_lo.array() > box_hi.array()).any()) return out;
    const double threshold_log_odds = octomap::logodds(threshold);
    for (auto it = tree_->begin_leafs_bbx(to_point(box_lo), to_point(box_hi)), end = tree_->end_leafs_bbx(); it != end;
         ++it) {
      if (it->getLogOdds() <= threshold_log_odds) continue;
      out.push_back(voxel(it.getCoordinate(), it.getSize(), *it));
    }
    return out;
  }

  std::optional<MapVoxel> at(const Vec3& p) const override {
    octomap::OcTreeKey key;
    if (!tree_->coordToKeyChecked(to_point(p), key)) return std::nullopt;
    const Node* node = tree_->search(key);
    if (node == nullptr) return std::nullopt;
    return voxel(tree_->keyToCoord(key), tree_->getResolution(), *node);
  }

  std::size_t leaves() const override { return tree_->getNumLeafNodes(); }
  std::size_t memory() const override { return tree_->memoryUsage(); }

  void write(const std::filesystem::path& file) override {
    maintain();
    if (!tree_->write(file.string())) throw IoError(file.string(), "cannot write the map");
  }

  void write_color(const std::filesystem::path& file, double threshold) override {
    maintain();
    octomap::ColorOcTree color(tree_->getResolution());
    for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
      octomap::ColorOcTreeNode* n = color.setNodeValue(it.getKey(), it->getLogOdds(), true);
      if (it->getOccupancy() > threshold) {
        const auto& rgb = semantic_class_info(it->belief().semantic).rgb;
        n->setColor(rgb[0], rgb[1], rgb[2]);
      }
    }
    if (color.size() > 0) color.updateInnerOccupancy();  // OctoMap 1.9 dereferences the missing root of an empty tree
    if (!color.write(file.string())) throw IoError(file.string(), "cannot write the colour OctoMap");
  }

  const void* tree() const override { return tree_.get(); }

 private:
  static constexpr std::uint32_t kNoSlot = ~std::uint32_t{0};
  static MapVoxel voxel(const octomap::point3d& c, double size, const Node& n) {
    const SemanticBelief b = n.belief();
    return {to_vec(c), size, n.getOccupancy(), b.semantic, b.probability};
  }

  std::unique_ptr<Tree> tree_;
  // Scratch kept between frames so that a frame allocates nothing once warm.
  FlatKeyIndex endpoints_;                    ///< voxels hit, by slot
  std::vector<octomap::point3d> first_point_;  ///< per slot: the first point that hit it (its ray's end)
  std::vector<std::uint32_t> point_slot_;
  std::vector<Node*> nodes_;
  FlatKeyIndex free_;                         ///< voxels crossed and not hit
  octomap::KeyRay ray_;
};

template <class Fusion>
std::unique_ptr<SemanticOcTree<Fusion>> make_tree(const SemanticMapConfig& c) {
  auto tree = std::make_unique<SemanticOcTree<Fusion>>(c.resolution_m);
  tree->setProbHit(c.prob_hit);
  tree->setProbMiss(c.prob_miss);
  tree->setClampingThresMin(c.clamp_min);
  tree->setClampingThresMax(c.clamp_max);
  tree->setOccupancyThres(c.occupancy_threshold);
  return tree;
}

void set_fusion_params(SemanticOcTree<MaxFusion>& t, const SemanticMapConfig& c) {
  t.fusion_params().disagreement_discount = static_cast<float>(c.max_fusion_discount);
}
void set_fusion_params(SemanticOcTree<BayesianHistogramFusion>&, const SemanticMapConfig&) {}

template <class Fusion>
std::unique_ptr<TreeOps> make_ops(std::unique_ptr<SemanticOcTree<Fusion>> tree, const SemanticMapConfig& c) {
  set_fusion_params(*tree, c);
  return std::make_unique<TreeOpsT<Fusion>>(std::move(tree));
}

}  // namespace semantic_map_ops

using semantic_map_ops::make_ops;
using semantic_map_ops::make_tree;
using semantic_map_ops::TreeOps;

struct SemanticMap::Impl {
  SemanticMapConfig config;
  std::unique_ptr<TreeOps> ops;
  FusionPolicy policy = FusionPolicy::kMax;
  Vec3 center = Vec3::Zero();
  std::optional<Vec3> pruned_at;
  int frames_since_maintenance = 0;

  Vec3 lo() const {
    const double h = 0.5 * config.window_size_m;
    return center - Vec3(h, h, config.window_below_m);
  }
  Vec3 hi() const {
    const double h = 0.5 * config.window_size_m;
    return center + Vec3(h, h, config.window_above_m);
  }
};

SemanticMap::SemanticMap(const SemanticMapConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  impl_->policy = config.fusion;
  if (config.fusion == FusionPolicy::kMax)
    impl_->ops = make_ops(make_tree<MaxFusion>(config), config);
  else
    impl_->ops = make_ops(make_tree<BayesianHistogramFusion>(config), config);
}
SemanticMap::SemanticMap(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SemanticMap::~SemanticMap() = default;
SemanticMap::SemanticMap(SemanticMap&&) noexcept = default;
SemanticMap& SemanticMap::operator=(SemanticMap&&) noexcept = default;

const SemanticMapConfig& SemanticMap::config() const { return impl_->config; }

void SemanticMap::set_window_center(const Vec3& p_W) {
  if (!p_W.allFinite()) throw Error("SemanticMap: window centre is not finite");
  impl_->center = p_W;
  if (!impl_->pruned_at || (p_W - *impl_->pruned_at).norm() >= impl_->config.prune_step_m) {
    impl_->ops->prune_outside(impl_->lo(), impl_->hi());
    impl_->pruned_at = p_W;
  }
}

Vec3 SemanticMap::window_center() const { return impl_->center; }

bool SemanticMap::in_window(const Vec3& p) const {
  const Vec3 lo = impl_->lo(), hi = impl_->hi();
  return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

InsertStats SemanticMap::insert(const SemanticPointCloud& cloud) {
  if (!cloud.origin_W.allFinite()) throw Error("SemanticMap: cloud origin is not finite");
  const InsertStats stats = impl_->ops->insert(cloud, impl_->lo(), impl_->hi());
  if (++impl_->frames_since_maintenance >= impl_->config.maintenance_interval) {
    impl_->ops->maintain();
    impl_->frames_since_maintenance = 0;
  }
  return stats;
}

MapVoxels SemanticMap::occupied_voxels() const {
  return impl_->ops->occupied(impl_->lo(), impl_->hi(), impl_->config.occupancy_threshold);
}

std::optional<MapVoxel> SemanticMap::voxel_at(const Vec3& p_W) const { return impl_->ops->at(p_W); }
std::size_t SemanticMap::leaf_count() const { return impl_->ops->leaves(); }
std::size_t SemanticMap::memory_bytes() const { return impl_->ops->memory(); }

void SemanticMap::save(const std::filesystem::path& file) const { impl_->ops->write(file); }

SemanticMap SemanticMap::load(const std::filesystem::path& file, SemanticMapConfig config) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(file.string(), "cannot open the map file");
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(in));
  if (!tree) throw IoError(file.string(), "not an OctoMap .ot file, or its tree type is unknown");
  if (in.fail()) throw IoError(file.string(), "truncated OctoMap file (the node data ends early)");
  auto impl = std::make_unique<Impl>();
  config.resolution_m = tree->getResolution();
  if (auto* max_tree = dynamic_cast<SemanticOcTree<MaxFusion>*>(tree.get())) {
    tree.release();
    config.fusion = FusionPolicy::kMax;
    impl->ops = make_ops(std::unique_ptr<SemanticOcTree<MaxFusion>>(max_tree), config);
  } else if (auto* bayes_tree = dynamic_cast<SemanticOcTree<BayesianHistogramFusion>*>(tree.get())) {
    tree.release();
    config.fusion = FusionPolicy::kBayes;
    impl->ops = make_ops(std::unique_ptr<SemanticOcTree<BayesianHistogramFusion>>(bayes_tree), config);
  } else {
    throw IoError(file.string(), "holds an OctoMap of type '" + tree->getTreeType() +
                                     "', not a navaid semantic map (SemanticOcTree-max or -bayes)");
  }
  impl->config = config;
  impl->policy = config.fusion;
  return SemanticMap(std::move(impl));
}

void SemanticMap::write_ply(const std::filesystem::path& file) const {
  const MapVoxels voxels = occupied_voxels();
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write the PLY file");
  out << "ply\nformat ascii 1.0\ncomment navaid semantic map: occupied voxel centres in W [m]\n"
      << "element vertex " << voxels.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      << "property uchar class_id\nproperty float class_probability\nproperty float occupancy\nend_header\n";
  for (const auto& v : voxels) {
    const auto& rgb = semantic_class_info(v.semantic).rgb;
    out << fmt::format("{:.4f} {:.4f} {:.4f} {} {} {} {} {:.4f} {:.4f}\n", v.center_W.x(), v.center_W.y(),
                       v.center_W.z(), rgb[0], rgb[1], rgb[2], static_cast<int>(v.semantic), v.class_probability,
                       v.occupancy);
  }
  if (!out) throw IoError(file.string(), "cannot write the PLY file");
}

void SemanticMap::write_color_octree(const std::filesystem::path& file) const {
  impl_->ops->write_color(file, impl_->config.occupancy_threshold);
}

const SemanticOcTree<MaxFusion>* SemanticMap::max_tree() const {
  return impl_->policy == FusionPolicy::kMax ? static_cast<const SemanticOcTree<MaxFusion>*>(impl_->ops->tree())
                                             : nullptr;
}
const SemanticOcTree<BayesianHistogramFusion>* SemanticMap::bayes_tree() const {
  return impl_->policy == FusionPolicy::kBayes
             ? static_cast<const SemanticOcTree<BayesianHistogramFusion>*>(impl_->ops->tree())
             : nullptr;
}

}  // namespace navaid::mapping
