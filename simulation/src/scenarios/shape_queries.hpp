#pragma once
// Small 2D geometry queries shared by the clearance rule and the voxelizer (private to the room).
#include <vector>

#include "navaid/simulation/world.hpp"

namespace navaid::simulation::detail {

/// Even-odd point-in-polygon test (either orientation).
bool point_in_polygon(const std::vector<Vec2>& poly, const Vec2& p);
/// Distance from p to the segment ab.
double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b);
/// Distance from p to the filled polygon (0 inside).
double polygon_distance(const std::vector<Vec2>& poly, const Vec2& p);
/// Distance from p to the filled rectangle centred at c with half sizes h, rotated by yaw.
double rectangle_distance(const Vec2& p, const Vec2& c, const Vec2& h, double yaw);
/// True when the segment ab passes through the open rectangle [lo, hi] (interior, not just edges).
bool segment_crosses_open_rect(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi);
/// True when the rotation only turns about W z (within tolerance); yaw is then returned.
bool is_upright(const Quat& q, double* yaw);

}  // namespace navaid::simulation::detail
