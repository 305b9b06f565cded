#pragma once
// eLabrador §III.C "Network Connectivity": segmentation runs on a cloud server, and the edge
// "periodically monitors network connectivity" and navigates without the cloud modules while the
// network is down. SegmentationLink is the edge's view of that server over a simulated network
// availability schedule, so that replays are deterministic:
//  - the network is down inside each configured outage [start_s, end_s) (recording seconds);
//  - the edge probes the server every check_period_s (probes at start + k * period);
//  - a probe sent while the network is down gets no reply, and the server is declared lost
//    timeout_s after that probe (the first probe inside an outage detects it);
//  - the first probe that finds the network up again restores the link at that probe;
//  - a frame gets labels only while the network is up and the link is up: inside an outage
//    nothing arrives, and after it the edge waits for its next probe before using the server.
// Outages shorter than the gap between probes lose their frames' labels without a state change.
#include <cstddef>
#include <optional>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"

namespace navaid::mapping {

struct NetworkOutage {
  double start_s = 0;  ///< seconds after the recording start
  double end_s = 0;    ///< exclusive; > start_s
};

struct SegmentationLinkConfig {
  std::vector<NetworkOutage> outages;  ///< in time order, not overlapping
  double check_period_s = 1.0;         ///< how often the edge probes the server
  double timeout_s = 0.5;              ///< how long a probe waits for its reply; < check_period_s
};

/// mapping.network.outages (a flat list of start_s, end_s pairs, e.g. [1.0, 2.0, 5.0, 6.5] for two
/// outages), mapping.network.check_period_s (1 s), mapping.network.timeout_s (0.5 s). nullopt when
/// mapping.network.outages is absent: the link is opt-in. Reversed, empty, unordered or overlapping
/// intervals raise ConfigError naming the key.
std::optional<SegmentationLinkConfig> read_segmentation_link_config(const Config& config);

enum class NetworkChangeKind { kLost, kRestored };

/// "lost" / "restored".
const char* network_change_name(NetworkChangeKind kind);

/// A change of the link's state as the edge detects it (mapping's own type: the interaction room
/// turns it into SystemEventKind::kNetworkLost / kNetworkRestored).
struct NetworkChange {
  Timestamp t = 0;
  NetworkChangeKind kind = NetworkChangeKind::kLost;
  bool operator==(const NetworkChange& o) const { return t == o.t && kind == o.kind; }
};

class SegmentationLink {
 public:
  /// `start`: the recording start the outages are relative to. Throws ConfigError on a bad config
  /// (as read_segmentation_link_config checks it).
  SegmentationLink(const SegmentationLinkConfig& config, Timestamp start);

  /// Whether the frame at `t` gets its labels from the server. Also records the state changes up
  /// to `t` (changes(), take_changes()); queries may come in any order.
  bool labels_available(Timestamp t);

  /// The simulated network itself (no detection delay).
  bool network_up(Timestamp t) const;
  /// The edge's belief: up until a lost change, down until the next restored one.
  bool link_up(Timestamp t) const;

  /// Every change up to the latest time queried, in time order.
  std::vector<NetworkChange> changes() const;
  /// The changes recorded since the last call (to announce each one once).
  std::vector<NetworkChange> take_changes();
  /// Every change the schedule will produce, known in advance (the network is simulated).
  const std::vector<NetworkChange>& schedule() const { return schedule_; }
  /// Outages detected so far (lost changes in changes()).
  std::size_t outages_detected() const;

 private:
  struct Interval {
    Timestamp start, end;  // absolute, [start, end)
  };
  std::vector<Interval> outages_;
  std::vector<NetworkChange> schedule_;
  std::size_t observed_ = 0;  // schedule_[0, observed_) happened at or before the latest query
  std::size_t taken_ = 0;     // schedule_[0, taken_) were handed out by take_changes()
};

}  // namespace navaid::mapping
