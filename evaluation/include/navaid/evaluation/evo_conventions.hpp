#pragma once
// evo's conventions (github.com/MichaelGrupp/evo, evo_ape / evo_rpe), for `navaid eval`'s evo
// aliases (docs/evaluation.md, "evo"):
//
// Association (evo.core.sync, --t_max_diff, default 0.01 s): the trajectory with fewer poses (the
// estimate when both have as many) is walked in order; each of its poses takes the nearest pose of
// the other (the first of equally near ones) when |dt| <= max_diff. Unlike rpg's rule
// (time_association.hpp) a pose of the longer trajectory may serve several poses.
//
// RPE pairs (evo.core.filters, --delta, --delta_unit f|m|d|r, --all_pairs), chosen on the aligned
// estimate's poses (on the reference's with --pairs_from_reference):
//   frames   consecutive: 0, delta, 2 delta, ...; all pairs: (i, i + delta);
//   metres   consecutive: the path is summed from the first pose and an index is taken each time it
//            reaches delta (then summed again from 0), so the first pose starts no pair; all pairs:
//            for each i the j > i whose path length from i is nearest delta, within tol;
//   angles   consecutive: rotation angles between neighbours summed from the first pose, a pair
//            (start, end) closed each time the sum reaches delta; all pairs: every (i, j > i) whose
//            direct rotation angle is within tol of delta.
//   tol = rel_delta_tol * delta (rel_delta_tol 0.1). No pair is an error.
// Error per pair (i, j): E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q the reference, P the aligned estimate;
// evo's default pose relation is its translation norm ("trans_part"); the rotation angle is kept too.
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/evaluation/error_statistics.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

/// evo's default --t_max_diff.
constexpr Duration kEvoDefaultMaxDiff = 10'000'000;

/// evo's association; pairs in the walked trajectory's order. navaid::Error for a non-positive
/// max_diff or unsorted times.
std::vector<PosePair> associate_poses_evo(const std::vector<io::StampedPose>& est,
                                          const std::vector<io::StampedPose>& gt, Duration max_diff = kEvoDefaultMaxDiff);

enum class RpeDeltaUnit { kFrames, kMeters, kDegrees, kRadians };
/// evo's letters: "f", "m", "d", "r".
std::optional<RpeDeltaUnit> rpe_delta_unit_from_string(std::string_view name);
std::string_view to_string(RpeDeltaUnit unit);

struct EvoRpeOptions {
  double delta = 1.0;
  RpeDeltaUnit unit = RpeDeltaUnit::kFrames;
  bool all_pairs = false;
  bool pairs_from_reference = false;
  double rel_delta_tol = 0.1;
};

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

/// The index pairs over `poses` (see above). navaid::Error on a non-positive delta, a non-integer
/// frame delta, an angle beyond 180 degrees / pi, or no pair at all (evo's message, in words).
IndexPairs evo_rpe_pairs(const std::vector<SE3>& poses, const EvoRpeOptions& options);

struct EvoRpeResult {
  EvoRpeOptions options;
  IndexPairs pairs;
  std::vector<double> translation_errors;   ///< [m]
  std::vector<double> rotation_errors_rad;  ///< [rad]
  ErrorStatistics translation;              ///< [m]
  ErrorStatistics rotation_deg;             ///< [deg]
};

/// RPE over matched pairs whose estimates are already aligned (`aligned_est[k]` belongs to
/// `pairs[k]`).
EvoRpeResult compute_rpe_evo(const std::vector<PosePair>& pairs, const std::vector<SE3>& aligned_est,
                             const EvoRpeOptions& options);

}  // namespace navaid::evaluation
