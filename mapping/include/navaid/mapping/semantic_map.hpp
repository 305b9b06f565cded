#pragma once
// The semantic voxel map: an OctoMap occupancy tree with a class belief per voxel (eLabrador
// §III-B), free space by ray casting (so that people and cars that leave are cleared), a local
// window that scrolls with the user and is pruned outside (memory bounded on any route), .ot
// save/load, PLY and octovis (ColorOcTree) export. This header stays free of OctoMap: the tree
// types are only forward-declared (semantic_octree.hpp has them).
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/mapping/map_voxel.hpp"
#include "navaid/mapping/semantic_point_cloud.hpp"

namespace navaid::mapping {

template <class Fusion>
class SemanticOcTree;
struct MaxFusion;
struct BayesianHistogramFusion;

enum class FusionPolicy { kMax, kBayes };

struct SemanticMapConfig {
  double resolution_m = 0.1;
  FusionPolicy fusion = FusionPolicy::kMax;
  double max_fusion_discount = 0.9;  ///< MaxFusion::Params::disagreement_discount
  // OctoMap's sensor model (its defaults): log-odds update of a hit / a miss, clamping bounds.
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  double occupancy_threshold = 0.5;  ///< p above which a voxel is occupied
  // The local window, centred on the user: a square of window_size_m (eLabrador: 10 m x 10 m),
  // from window_below_m under to window_above_m over the user's position.
  double window_size_m = 10.0;
  double window_below_m = 3.0;
  double window_above_m = 2.5;
  /// The window is re-pruned once its centre moved this far since the last pruning.
  double prune_step_m = 0.5;
  /// Frames between refreshes of inner nodes and collapses of equal children (OctoMap's prune()).
  int maintenance_interval = 10;
};

/// Keys under mapping.map.*: resolution_m, fusion (max | bayes), max_fusion_discount, prob_hit,
/// prob_miss, clamp_min, clamp_max, occupancy_threshold, window_size_m, window_below_m,
/// window_above_m, prune_step_m, maintenance_interval.
SemanticMapConfig read_semantic_map_config(const Config& config);

struct InsertStats {
  std::size_t points = 0;            ///< points of the cloud
  std::size_t outside_window = 0;    ///< points dropped because they fall outside the window
  std::size_t occupied_voxels = 0;   ///< distinct voxels hit
  std::size_t free_voxels = 0;       ///< distinct voxels a ray crossed (and no point hit)
};

class SemanticMap {
 public:
  explicit SemanticMap(const SemanticMapConfig& config = {});
  ~SemanticMap();
  SemanticMap(SemanticMap&&) noexcept;
  SemanticMap& operator=(SemanticMap&&) noexcept;

  const SemanticMapConfig& config() const;

  /// Centres the window on the user; deletes every voxel outside it once the centre has moved
  /// prune_step_m since the last pruning (and on the first call).
  void set_window_center(const Vec3& p_W);
  Vec3 window_center() const;
  /// True when p_W lies inside the current window.
  bool in_window(const Vec3& p_W) const;

  /// Ray-casts the cloud from its origin: voxels crossed become freer, voxels hit more occupied
  /// and absorb the points' class votes in order (the fusion policy). Points outside the window
  /// are dropped (their rays are not cast).
  InsertStats insert(const SemanticPointCloud& cloud);

  /// Occupied voxels (p > occupancy_threshold) inside the window.
  MapVoxels occupied_voxels() const;
  /// The voxel at p_W, nullopt when unknown (never observed, or pruned away).
  std::optional<MapVoxel> voxel_at(const Vec3& p_W) const;

  std::size_t leaf_count() const;
  std::size_t memory_bytes() const;

  /// Writes the tree as an OctoMap .ot file (tree id "SemanticOcTree-max" / "-bayes").
  void save(const std::filesystem::path& file) const;
  /// Reads a .ot written by save(); the fusion policy and resolution come from the file, the rest
  /// of `config` is kept. Throws IoError naming the file when it is missing, corrupt, truncated or
  /// holds another tree type.
  static SemanticMap load(const std::filesystem::path& file, SemanticMapConfig config = {});
  /// ASCII PLY of the occupied voxel centres, coloured by class (properties: class id, class
  /// probability, occupancy).
  void write_ply(const std::filesystem::path& file) const;
  /// An octomap::ColorOcTree .ot with class colours, which octovis and ROS tools display.
  void write_color_octree(const std::filesystem::path& file) const;

  /// The tree behind the map (one of the two is non-null), for the 3D ESDF and tests.
  const SemanticOcTree<MaxFusion>* max_tree() const;
  const SemanticOcTree<BayesianHistogramFusion>* bayes_tree() const;

  struct Impl;

 private:
  explicit SemanticMap(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::mapping
