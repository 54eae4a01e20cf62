#include "place/keyframe_places.h"

#include <algorithm>

namespace plslam {

KeyframePlaces::KeyframePlaces(std::shared_ptr<const VocabularySet> vocabulary) : vocabulary_(std::move(vocabulary)) {
  if (vocabulary_ && vocabulary_->orb.empty()) vocabulary_.reset();
}

FrameWords KeyframePlaces::describe(const FrameFeatures& features) const { return describeWords(*vocabulary_, features); }

void KeyframePlaces::add(Id id, const FrameFeatures& features) {
  if (enabled()) add(id, describe(features));
}

void KeyframePlaces::add(Id id, FrameWords words) {
  if (!enabled()) return;
  database_.add(id, words.bow);
  words_[id] = std::move(words);
}

const FrameWords* KeyframePlaces::words(Id id) const {
  const auto it = words_.find(id);
  return it == words_.end() ? nullptr : &it->second;
}

std::vector<PlaceScore> KeyframePlaces::query(const FrameWords& frame, const PlaceQueryOptions& o) const {
  std::vector<PlaceScore> out;
  for (const DatabaseScore& s : database_.query(frame.bow)) {
    const FrameWords& kf = words_.at(s.keyframe);
    const double wl = !frame.bow.lbd.empty() && !kf.bow.lbd.empty() ? o.line_weight : 0.0;
    const double total = o.point_weight + wl;
    if (total > 0) out.push_back({s.keyframe, (o.point_weight * s.orb + wl * s.lbd) / total});
  }
  std::stable_sort(out.begin(), out.end(), [](const PlaceScore& a, const PlaceScore& b) { return a.score > b.score; });
  const double floor = out.empty() ? 0.0 : o.min_relative_score * out.front().score;
  size_t keep = 0;
  while (keep < out.size() && static_cast<int>(keep) < o.max_candidates && out[keep].score >= floor) ++keep;
  out.resize(keep);
  return out;
}

}  // namespace plslam
