#pragma once
// One search core for every planner of the room (the nav2 Smac pattern: one templated A* over
// node types). A planner describes its search space; the core does the bookkeeping: open list,
// closed set, parents, limits, and the answer. Grid A*, Direction A* (many goals, each with its
// own terminal cost) and the walking-path generator's footstep search are all this one function.
//
// A Space provides
//   using State = ...;                       // what a node is (a cell, a footstep, ...)
//   std::uint64_t key(const State&) const;   // states with equal keys are the same node
//   template <class Emit> void expand(const State& s, Emit&& emit) const;
//                                            // calls emit(next, edge_cost) per successor, cost >= 0
//   double heuristic(const State&) const;    // lower bound of the remaining cost, terminal included
//   std::optional<double> goal_cost(const State&) const;
//                                            // nullopt: not a goal; else its terminal cost >= 0
// and optionally, for dense keys in [0, key_count()) stored in flat arrays instead of a hash map:
//   static constexpr bool kDenseKeys = true; std::size_t key_count() const;
//
// The search minimises g(path) + goal_cost(last state). A goal is not the end when it is popped:
// its finishing entry (f = g + goal_cost) goes back on the open list, so with an admissible
// heuristic the first finishing entry popped is the best over all goals (Direction A*'s one
// search toward n_s targets equals the best of n_s separate searches). Ties are broken by larger
// g, then by insertion order, so results are deterministic.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <queue>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace navaid::planning {

/// Limits that bound every search: it never hangs on a map without a path.
struct SearchLimits {
  std::size_t max_expansions = 4'000'000;  ///< nodes taken off the open list
  double max_time_s = 0.0;                 ///< wall-clock limit; 0 = none (replay stays deterministic)
};

enum class SearchStatus { kFound, kNoPath, kExpansionLimit, kTimeLimit };

template <class State>
struct SearchResult {
  SearchStatus status = SearchStatus::kNoPath;
  std::vector<State> path;      ///< start ... goal (empty unless kFound)
  double cost = std::numeric_limits<double>::infinity();  ///< g(goal) + goal_cost(goal)
  double path_cost = std::numeric_limits<double>::infinity();  ///< g(goal) alone
  std::size_t expanded = 0;     ///< nodes expanded (closed)
  std::size_t generated = 0;    ///< successors offered by the space (before duplicate pruning)
  double time_s = 0.0;
  bool found() const { return status == SearchStatus::kFound; }
};

namespace detail {

template <class Space, class = void>
struct HasDenseKeys : std::false_type {};
template <class Space>
struct HasDenseKeys<Space, std::enable_if_t<Space::kDenseKeys>> : std::true_type {};

/// key -> node record index: flat array for dense keys, hash map otherwise.
template <class Space, bool Dense = HasDenseKeys<Space>::value>
class NodeIndex {
 public:
  explicit NodeIndex(const Space& space) : slots_(space.key_count(), kNone) {}
  std::uint32_t find(std::uint64_t key) const { return key < slots_.size() ? slots_[key] : kNone; }
  void set(std::uint64_t key, std::uint32_t node) { slots_[key] = node; }
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

 private:
  std::vector<std::uint32_t> slots_;
};

template <class Space>
class NodeIndex<Space, false> {
 public:
  explicit NodeIndex(const Space&) {}
  std::uint32_t find(std::uint64_t key) const {
    const auto it = slots_.find(key);
    return it == slots_.end() ? kNone : it->second;
  }
  void set(std::uint64_t key, std::uint32_t node) { slots_[key] = node; }
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

 private:
  std::unordered_map<std::uint64_t, std::uint32_t> slots_;
};

}  // namespace detail

template <class Space>
SearchResult<typename Space::State> best_first_search(const Space& space, const typename Space::State& start,
                                                      const SearchLimits& limits = {}) {
  using State = typename Space::State;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  SearchResult<State> result;

  struct Node {
    State state;
    double g;
    std::uint32_t parent;
    bool closed;
  };
  struct Entry {
    double f;
    double g;  // larger g first among equal f (deeper nodes finish sooner)
    std::uint64_t order;
    std::uint32_t node;
    bool finishing;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const {
      if (a.f != b.f) return a.f > b.f;
      if (a.finishing != b.finishing) return b.finishing;
      if (a.g != b.g) return a.g < b.g;
      return a.order > b.order;
    }
  };

  constexpr std::uint32_t kNone = detail::NodeIndex<Space>::kNone;
  detail::NodeIndex<Space> index(space);
  std::vector<Node> nodes;
  std::priority_queue<Entry, std::vector<Entry>, Later> open;
  std::uint64_t order = 0;

  const auto finish = [&](SearchStatus status) {
    result.status = status;
    result.time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
  };

  nodes.push_back(Node{start, 0.0, kNone, false});
  index.set(space.key(start), 0);
  open.push(Entry{space.heuristic(start), 0.0, order++, 0, false});

  while (!open.empty()) {
    const Entry top = open.top();
    open.pop();
    if (top.finishing) {
      for (std::uint32_t n = top.node; n != kNone; n = nodes[n].parent) result.path.push_back(nodes[n].state);
      std::reverse(result.path.begin(), result.path.end());
      result.cost = top.f;
      result.path_cost = nodes[top.node].g;
      return finish(SearchStatus::kFound);
    }
    Node& node = nodes[top.node];
    if (node.closed || top.g > node.g) continue;  // a stale entry: a cheaper one was expanded
    if (result.expanded >= limits.max_expansions) return finish(SearchStatus::kExpansionLimit);
    if (limits.max_time_s > 0.0 && (result.expanded & 1023U) == 0 &&
        std::chrono::duration<double>(Clock::now() - t0).count() > limits.max_time_s) {
      return finish(SearchStatus::kTimeLimit);
    }
    node.closed = true;
    ++result.expanded;
    const std::uint32_t current = top.node;
    const double g = node.g;
    if (const std::optional<double> terminal = space.goal_cost(node.state)) {
      open.push(Entry{g + *terminal, g, order++, current, true});
    }
    // `node` may dangle once nodes grows: copy what the successors need.
    const State state = node.state;
    space.expand(state, [&](const State& next, double edge_cost) {
      ++result.generated;
      const double g_next = g + edge_cost;
      const std::uint64_t key = space.key(next);
      std::uint32_t id = index.find(key);
      if (id == kNone) {
        id = static_cast<std::uint32_t>(nodes.size());
        nodes.push_back(Node{next, g_next, current, false});
        index.set(key, id);
      } else if (nodes[id].closed || g_next >= nodes[id].g) {
        return;
      } else {
        nodes[id].state = next;
        nodes[id].g = g_next;
        nodes[id].parent = current;
      }
      open.push(Entry{g_next + space.heuristic(next), g_next, order++, id, false});
    });
  }
  return finish(SearchStatus::kNoPath);
}

}  // namespace navaid::planning
