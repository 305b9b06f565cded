#pragma once
// The walking-path generator's "holonomic with obstacles" heuristic (as in hybrid A*, which the
// Smart Cane paper builds on): the shortest 8-connected distance to the goal over a coarse grid
// whose cells are passable where no map cell inside them is an obstacle (so a thin wall between
// two rooms blocks, and a door two coarse cells wide leaves a way through) and one leaves the
// body's clearance (gaps too narrow for the body do not count). It sees walls and dead ends that
// the straight distance does not, so the footstep search no longer floods rooms that lead away
// from the goal. Where the coarse distance is below the straight distance the straight distance
// is used, and one coarse-cell diagonal is taken off the coarse distance.
//
// The coarse search runs from the goal toward the footstep search's start, as A* with the octile
// distance to the start (consistent, so a settled cell's distance is exact), and is resumed on
// demand (reverse resumable A*, Silver 2005): a query continues it until the queried cell is
// settled. Coarse cells are classified when the search first reaches them. So the work follows the
// corridor the footstep search walks rather than the area of the map. A cell on the search's
// frontier answers with its tentative distance (the length of a real coarse path), and a resumed
// query settles at most kResumeBudget cells (the first query, the start, settles whatever it takes).
#include <limits>
#include <queue>
#include <vector>

#include "navaid/mapping/esdf_2d.hpp"

namespace navaid::planning {

class GridDistanceHeuristic {
 public:
  /// `clearance_m`: what a map cell needs by the ESDF to be walkable. `cell_m`: the coarse cell
  /// (rounded to a whole number of map cells).
  GridDistanceHeuristic(const mapping::Esdf2d& esdf, const mapping::Vec2& goal_W, const mapping::Vec2& start_W,
                        double cell_m, double clearance_m);

  /// Estimate of the walkable distance from p_W to the goal [m]; +inf where the coarse grid does
  /// not connect p_W to the goal (or p_W is off the map). In a blocked coarse cell (next to a
  /// wall, in a door) the way goes through its passable neighbours, and the straight distance when
  /// it has none. Cells farther than 4x the start's straight distance are not settled: for them
  /// the bound the search has proven is returned. Not const: it may resume the search.
  double at(const mapping::Vec2& p_W);
  /// Coarse cells settled so far (a measure of the work done).
  std::size_t settled() const { return settled_count_; }

 private:
  enum : std::uint8_t { kUnknown = 0, kPassable = 1, kBlocked = 2 };
  bool passable(int cell);
  void settle_until(int cell, std::size_t budget);
  /// The first query (the start) settles its cell whatever it takes; later ones resume the
  /// search by at most this many cells, then fall back to the bound the search has proven.
  static constexpr std::size_t kResumeBudget = 256;
  bool first_query_ = true;

  const mapping::Esdf2d& esdf_;
  float to_start(int cell) const;
  double coarse_distance(int cell);

  mapping::Vec2 origin_, goal_;
  int start_x_ = 0, start_y_ = 0;
  double cell_;
  double clearance_;
  int per_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<float> distance_;
  std::vector<std::uint8_t> settled_;
  std::vector<std::uint8_t> kind_;
  struct Entry {
    float f;  ///< distance + octile distance to the start
    float g;  ///< distance (ties: the deeper entry first)
    int cell;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const { return a.f != b.f ? a.f > b.f : a.g < b.g; }
  };
  std::priority_queue<Entry, std::vector<Entry>, Later> open_;
  std::size_t settled_count_ = 0;
  float f_limit_ = 0.0F;
};

}  // namespace navaid::planning
