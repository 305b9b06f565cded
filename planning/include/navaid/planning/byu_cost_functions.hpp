#pragma once
// The BYU augmented cane's two obstacle cost functions and its rumble table (thesis Ch. 2, "Cost
// Functions" and "Haptic Feedback", eq. 2.11-2.15, Tables 2.1 and 2.2, source appendix D.3-D.5).
//
// Both functions read the nearest-point scan (mapping::ObstacleScan, frame U: bearing 0 ahead along
// the cane, positive to the left; ranges are horizontal). The thesis measures its polar angle
// phi in the levelled sensor frame with 90 deg straight ahead: phi = bearing + 90 deg. Every angle
// below is the bearing alpha, |alpha| its magnitude.
//
// Intended user path (eq. 2.11), width w and distance d: in the thesis's phi the path's lateral
// edges are the lines |x| = w/2 and its front the arc of radius d, which meet at
// gamma = arccos((w/2)/d) (eq. 2.11's gamma). In bearings that is
//     P(alpha) = min(d, (w/2) / |sin alpha|),
// the front arc over |alpha| <= asin((w/2)/d) = 90 deg - gamma and the edge lines outside it (the
// FICF source, D.3, builds the same boundary from asin(width/distance) with width = w/2). The printed
// eq. 2.11 writes the edges as (w/2) csc(phi) on [0, 61 deg + gamma] and [119 deg - gamma, 180];
// those intervals and csc(phi) only make sense for the angle from straight ahead, which is what we
// use.
//
// FICF (Fully-Integrated, w = 0.75 m, d = 3.5 m = the Xtion's range), per bin of range r:
//   r < P(alpha):        C_F += exp(4.5 - r) / 100                                  (eq. 2.12)
//   P(alpha) < r < d:    C_L or C_R += exp((e - |alpha|) / (e - asin((w/2)/r)) + 3.5 - r) / 100
//                                                                                   (eq. 2.13)
//   with e = pi/6 in the thesis (the half width of its +-30 deg scan; max_bearing here). The
//   fraction is 1 on the path's edge and 0 at the scan's edge: "obstacles closer to the intended
//   user path are weighted higher" (Sec. 4.1). Printed eq. 2.13 has asin(w / r) and "when
//   r_np < r_iup"; the text before it ("greater for the nearest point laser scan than for the
//   intended user path") and D.3 (width = 0.375 = w/2, r > boundary and r < 3.5) give w/2 and
//   r > P, which also keeps the denominator positive (r > (w/2)/sin|alpha| means
//   asin((w/2)/r) < |alpha| <= e).
// CACF (Cushioned Avoidance): the intended path (lower cushion SC_lb) with w = 0.5 m, d = 2.0 m and a
// wider cushion SC_ub from eq. 2.11 with w = 1.5 m, d = 2.0 m:
//   r < SC_lb(alpha):             C_F += (d - r)^2                                   (eq. 2.14)
//   SC_lb(alpha) <= r < SC_ub:    C_L or C_R += (SC_ub(alpha) - r)^2                (eq. 2.15)
//   Printed eq. 2.14 reads r_np^2, which would fall as an obstacle comes nearer; D.4 adds
//   pow(distance_lb - r, 2), which rises: we use D.4's (d - r)^2.
//
// Where the appendix code departs from the text we follow the text (and say so): D.3's forward loop
// covers bins 30 - gamma .. 30 + 2 gamma (not symmetric), its side weights use |i| deg of the
// array index instead of the bearing, D.3 gives an obstacle inside the path's side band no cost at
// all (the text: C_F for every r < r_iup), and D.4 takes the cushion's corner angle as
// floor / ceil(atan2(w/2, d)) of the flat-fronted box instead of eq. 2.11's arc. Bins straight
// ahead (alpha = 0) belong to neither side (with the defaults they never carry a side cost). Bins
// beyond max_bearing are ignored (the thesis scan ends at +-30 deg). Each bin's cost is weighted
// by its width / 1 deg, so the Table 2.2 thresholds (calibrated on 1 deg bins) keep their meaning
// at other bin widths. Drop-offs (drop_off_ranges: ground below the plane, a kerb or a step down)
// count as obstacles at their range (the nearer of the two per bin): the thesis's ground filter
// would drop them silently, but stepping off a kerb is the fall the cane exists to prevent.
#include <optional>
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/obstacle_scan.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::planning {

enum class ByuCostFunction { kFicf, kCacf };
std::string_view to_string(ByuCostFunction function);
/// "ficf" or "cacf"; nullopt for anything else.
std::optional<ByuCostFunction> byu_cost_function_from_string(std::string_view name);

/// Table 2.2.
struct ByuThresholds {
  double forward = 0.0;
  double left_right = 0.0;
};

struct FicfConfig {
  double width_m = 0.75;    ///< w of the intended user path
  double distance_m = 3.5;  ///< d: the Xtion Pro Live's range; side costs only below it
  ByuThresholds thresholds{3.0, 6.0};
};

struct CacfConfig {
  double width_m = 0.5;             ///< w of the intended user path (lower safety cushion)
  double distance_m = 2.0;          ///< its d
  double cushion_width_m = 1.5;     ///< w of the upper safety cushion
  double cushion_distance_m = 2.0;  ///< its d
  ByuThresholds thresholds{3.8, 7.0};
};

struct ByuCostConfig {
  FicfConfig ficf;
  CacfConfig cacf;
  /// Bins with |bearing| above this are ignored; also e of eq. 2.13 (pi/6 in the thesis).
  double max_bearing_rad = 0.5235987755982988;  // 30 deg
  bool drop_offs_are_obstacles = true;
};

/// Keys planning.byu.*: ficf.width_m, ficf.distance_m, ficf.forward_threshold,
/// ficf.left_right_threshold, cacf.width_m, cacf.distance_m, cacf.cushion_width_m,
/// cacf.cushion_distance_m, cacf.forward_threshold, cacf.left_right_threshold, max_bearing_deg,
/// drop_offs_are_obstacles. Throws ConfigError on a value out of range, a path wider than twice its
/// distance (no gamma), or a CACF cushion narrower or shorter than the intended path.
ByuCostConfig read_byu_cost_config(const Config& config);

const ByuThresholds& byu_thresholds(ByuCostFunction function, const ByuCostConfig& config);

/// Eq. 2.11 at bearing alpha [rad]: min(d, (w/2)/|sin alpha|) [m].
double intended_path_range(double bearing_rad, double width_m, double distance_m);
/// Eq. 2.11's gamma = arccos((w/2)/d) [rad] in the thesis's phi (90 deg ahead); the front arc spans
/// |bearing| <= pi/2 - gamma. Requires 0 < w/2 <= d.
double intended_path_gamma(double width_m, double distance_m);

/// One bin's terms (a bin of 1 deg). Eq. 2.12.
double ficf_forward_term(double range_m);
/// Eq. 2.13 with e = edge_rad; requires r > (w/2)/|sin alpha| (outside the path), |alpha| <= e.
double ficf_side_term(double bearing_rad, double range_m, double width_m, double edge_rad);
/// Eq. 2.14 as in D.4: (d - r)^2.
double cacf_forward_term(double range_m, double distance_m);
/// Eq. 2.15: (SC_ub - r)^2.
double cacf_side_term(double range_m, double upper_cushion_m);

struct ByuCosts {
  double forward = 0.0;  ///< C_F
  double left = 0.0;     ///< C_L
  double right = 0.0;    ///< C_R
};

/// Throws navaid::Error for a scan it cannot read (bins with a non-positive width, a negative
/// range, drop_off_ranges of another length than ranges; empty drop_off_ranges means none).
ByuCosts ficf_costs(const mapping::ObstacleScan& scan, const ByuCostConfig& config);
ByuCosts cacf_costs(const mapping::ObstacleScan& scan, const ByuCostConfig& config);
ByuCosts byu_costs(const mapping::ObstacleScan& scan, ByuCostFunction function, const ByuCostConfig& config);

/// Table 2.1, with D.5's comparisons:
///   C_F <= forward threshold                                   -> off (D.5: "C_F > T_F" rumbles)
///   C_L < C_R and C_L < left-right threshold                   -> left  (the left is freer)
///   C_R < C_L and C_R < left-right threshold                   -> right
///   otherwise                                                  -> both (stop and search)
/// Table 2.1's rows overlap: with C_L < C_R and both above the left-right threshold rows 2 and 4
/// both hold; row 4 ("both rumble = stop") wins, as in the text ("when both the left and right
/// cost values exceed a second threshold") and in D.5. Only the freer side's cost has to be below
/// the threshold for a side signal: C_L < T_LR < C_R gives left. A tie C_L = C_R (e.g. both 0 in
/// front of a wall) has no freer side: both, as D.5's else branch; sides within 1e-9 (relative) of
/// each other are a tie, so rounding never picks a side. A side cost equal to the threshold is not
/// free (D.5's strict <).
RumbleState rumble_state(const ByuCosts& costs, const ByuThresholds& thresholds);

/// The GuidanceCommand of one scan's rumble state: go, path-found when off, obstacle-ahead
/// otherwise; confidence 1 (the scan is in the cane's own frame: no pose uncertainty in it).
GuidanceCommand rumble_command(Timestamp t, RumbleState state);

/// One command from one scan. The rumble is always given, whatever the estimator's mode: the scan
/// lives in frame U (levelled by the scan's own ground plane), needs neither position nor yaw, and
/// withholding an obstacle warning while the estimator initializes or is lost would take away the
/// only warning the user has. (The path planners withhold their commands then: they need the pose.)
///   off   -> go, path-found, heading 0 (along the cane), look-ahead d of the function;
///   left / right -> go, obstacle-ahead, no heading (the thesis gives a side, not an angle; `rumble`
///           carries it);
///   both  -> stop, obstacle-ahead.
/// Confidence is 1, except when frame U itself came from the estimate (ground source kPrior: no
/// measured ground plane, the estimate's attitude levelled the scan) and the estimate is
/// initializing or lost: then confidence 0 and no heading / look-ahead, but the rumble stays.
GuidanceCommand byu_guidance(const mapping::ObstacleScan& scan, EstimatorMode mode, ByuCostFunction function,
                             const ByuCostConfig& config);

}  // namespace navaid::planning
