#include "navaid/estimation/feature_track_store.hpp"

#include <algorithm>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

void FeatureTrackStore::add_frame(std::uint64_t frame_id,
                                  const std::vector<std::pair<std::uint64_t, TrackObservation>>& observations) {
  if (last_frame_ && frame_id <= *last_frame_)
    throw Error("FeatureTrackStore: frame ids must increase (got " + std::to_string(frame_id) + " after " +
                std::to_string(*last_frame_) + ")");
  last_frame_ = frame_id;
  for (const auto& [track_id, obs] : observations) {
    FeatureTrack& track = tracks_[track_id];
    track.id = track_id;
    TrackObservation o = obs;
    o.frame_id = frame_id;
    track.observations.push_back(o);
  }
}

void FeatureTrackStore::remove_frame(std::uint64_t frame_id) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    auto& obs = it->second.observations;
    obs.erase(std::remove_if(obs.begin(), obs.end(), [&](const TrackObservation& o) { return o.frame_id == frame_id; }),
              obs.end());
    it = obs.empty() ? tracks_.erase(it) : std::next(it);
  }
}

std::vector<std::uint64_t> FeatureTrackStore::anchored_at(std::uint64_t frame_id) const {
  std::vector<std::uint64_t> ids;
  for (const auto& [id, track] : tracks_)
    if (track.anchor().frame_id == frame_id) ids.push_back(id);
  return ids;
}

const TrackObservation* FeatureTrackStore::find(const FeatureTrack& track, std::uint64_t frame_id) {
  for (const auto& o : track.observations)
    if (o.frame_id == frame_id) return &o;
  return nullptr;
}

double FeatureTrackStore::mean_parallax_px(std::uint64_t frame_a, std::uint64_t frame_b, int* common) const {
  double sum = 0;
  int n = 0;
  for (const auto& [id, track] : tracks_) {
    const TrackObservation* a = find(track, frame_a);
    const TrackObservation* b = a ? find(track, frame_b) : nullptr;
    if (!b) continue;
    sum += (a->uv - b->uv).norm();
    ++n;
  }
  if (common) *common = n;
  return n > 0 ? sum / n : 0.0;
}

}  // namespace navaid::estimation
