#pragma once
// How good a semantic map is, against a simulated world whose every primitive is known:
// occupancy precision / recall / F1 near the walked path, semantic accuracy per class, and recall
// of the obstacles the scenario puts in the user's way: its deliberate obstacles (on the path: low
// branches, the head-high hanging obstacle) and its placed ones (beside the path: the corridor's
// low box, hanging sign and cabinet, the waist-high hanging obstacle).
//
// The local window forgets what the user left behind, so quality is accumulated over snapshots
// taken during the walk: at each, the map's voxels within path_radius_m (horizontally) of the user
// are compared with the truth, and each truth / map cell keeps the verdict of the last snapshot
// that saw it. Truth voxels are those of simulation::voxelize at the map's resolution on the map's
// own grid (cells aligned with OctoMap's). A mapped voxel is correct when a truth voxel lies within
// tolerance_voxels of it (Chebyshev distance); a truth surface voxel counts for recall only once
// the map has observed it or a neighbour (interiors of solids and what no ray reached are not
// counted against the map).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "navaid/mapping/semantic_map.hpp"
#include "navaid/simulation/occupancy_export.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::evaluation {

struct MapQualityConfig {
  double path_radius_m = 5.0;
  int tolerance_voxels = 1;
};

struct ClassAccuracy {
  std::size_t correct = 0, total = 0;  ///< mapped voxels matched to truth voxels of this class
};

struct DeliberateObstacleResult {
  std::uint32_t primitive = 0;
  bool on_path = true;    ///< Scenario::deliberate_obstacles (else placed_obstacles, beside the path)
  SemanticClass semantic = SemanticClass::kUnlabeled;
  double min_z_m = 0, max_z_m = 0;  ///< vertical extent (a hanging obstacle starts high)
  bool in_reach = false;  ///< some of its voxels came within path_radius_m of the user
  bool detected = false;  ///< a mapped occupied voxel touched it (within tolerance)
};

struct MapQuality {
  std::size_t true_positive = 0, false_positive = 0, false_negative = 0;
  double precision = 0, recall = 0, f1 = 0;
  std::map<SemanticClass, ClassAccuracy> per_class;
  double semantic_accuracy = 0;  ///< over all labelled matched voxels
  std::vector<DeliberateObstacleResult> deliberate;
  double deliberate_recall = 0;  ///< detected / in reach, all obstacles (0 when none came in reach)
  double on_path_recall = 0;     ///< the same over the deliberate (on-path) obstacles only
  std::size_t in_reach = 0, on_path_in_reach = 0;  ///< the recalls' denominators
  std::size_t detected = 0, on_path_detected = 0;  ///< and numerators
  std::size_t snapshots = 0;
};

class MapQualityAccumulator {
 public:
  /// Voxelizes the scenario's deliberate obstacles now and its static world tile by tile (10 m
  /// tiles, voxelized when the user first comes near, dropped when far behind) at the map's
  /// resolution, from ground_z - 1 m to ground_z + 4 m.
  MapQualityAccumulator(const simulation::Scenario& scenario, double resolution_m, const MapQualityConfig& config = {});
  ~MapQualityAccumulator();
  MapQualityAccumulator(const MapQualityAccumulator&) = delete;
  MapQualityAccumulator& operator=(const MapQualityAccumulator&) = delete;

  /// The transform from the map's world (the estimator's W) into the scenario's world; identity
  /// by default (ground-truth poses). With estimated poses: evaluation::first_state_transform,
  /// so that the drift after the first state is what the map is charged for.
  void set_map_to_truth(const SE3& T_truth_map);

  /// Compares the map near the user with the truth (the user at user_W in the map's world).
  void add_snapshot(const mapping::SemanticMap& map, const Vec3& user_W);
  MapQuality result() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::evaluation
