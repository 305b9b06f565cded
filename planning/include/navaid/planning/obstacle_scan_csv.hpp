#pragma once
// Reader of the obstacle_scan.csv that `navaid map --set mapping.obstacles.enabled=true` writes
// (apps/map_session.cpp, docs/mapping.md): one row per mapped frame,
//     t_ns,ground,ransac,obstacle_points,drop_off_points,r_<bearing deg>,...
// ground = the GroundSource as an integer (0 RANSAC, 1 running average after a rejected plane,
// 2 running average without a plane, 3 the prior), ransac 0/1, the two point counts, then the
// nearest obstacle range [m] per bin (empty: nothing in the bin).
//
// It lives in planning, not io: io depends on core only (DESIGN.md §2) and ObstacleScan is a
// mapping type.
//
// What the file does not hold stays empty: nearest_U NaN, drop_off_ranges +inf (the file gives
// only the drop-off point count, not their bins), T_U_C identity, the plane default. Bin bearings
// come from the header's labels, which are rounded to whole degrees: the first label is bin 0's
// centre and the increment (last - first) / (bins - 1) (1 deg for a single bin); every label must
// lie within half a degree of its bin's centre.
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "navaid/mapping/obstacle_scan.hpp"

namespace navaid::planning {

/// Throws navaid::IoError (file, line) on a file that cannot be opened, an empty file, a wrong
/// header, a wrong column count, a field that is not a number of its kind (or out of range: a
/// negative or non-finite range, a ground source outside 0..3, ransac not 0/1), and time stamps
/// that do not increase.
std::vector<mapping::ObstacleScan> read_obstacle_scan_csv(const std::filesystem::path& file);
/// The same from a stream; `name` stands for the file in messages.
std::vector<mapping::ObstacleScan> parse_obstacle_scan_csv(std::istream& in, const std::string& name);

}  // namespace navaid::planning
