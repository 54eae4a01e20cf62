#include "place/keyframe_database.h"

#include <algorithm>
#include <cmath>

namespace plslam {

KeyframeBow describeBow(const VocabularySet& vocabulary, const FrameFeatures& f) {
  KeyframeBow b;
  b.orb = vocabulary.orb.transform(f.point_descriptors);
  b.lbd = vocabulary.lbd.transform(f.line_descriptors);
  return b;
}

void KeyframeDatabase::addTo(Index* index, Id keyframe, const BowVector& v) {
  for (const auto& [w, value] : v) (*index)[w].emplace_back(keyframe, value);
}

void KeyframeDatabase::removeFrom(Index* index, Id keyframe, const BowVector& v) {
  for (const auto& [w, value] : v) {
    auto it = index->find(w);
    if (it == index->end()) continue;
    auto& list = it->second;
    list.erase(std::remove_if(list.begin(), list.end(), [&](const auto& e) { return e.first == keyframe; }), list.end());
    if (list.empty()) index->erase(it);
  }
}

void KeyframeDatabase::add(Id keyframe, KeyframeBow bow) {
  remove(keyframe);
  addTo(&orb_index_, keyframe, bow.orb);
  addTo(&lbd_index_, keyframe, bow.lbd);
  bows_[keyframe] = std::move(bow);
}

void KeyframeDatabase::remove(Id keyframe) {
  auto it = bows_.find(keyframe);
  if (it == bows_.end()) return;
  removeFrom(&orb_index_, keyframe, it->second.orb);
  removeFrom(&lbd_index_, keyframe, it->second.lbd);
  bows_.erase(it);
}

const KeyframeBow* KeyframeDatabase::bow(Id keyframe) const {
  auto it = bows_.find(keyframe);
  return it == bows_.end() ? nullptr : &it->second;
}

std::vector<DatabaseScore> KeyframeDatabase::query(const KeyframeBow& q) const {
  std::map<Id, DatabaseScore> acc;
  // L1 score accumulated over common words: 0.5 * sum (|a| + |b| - |a - b|).
  auto visit = [&](const Index& index, const BowVector& v, bool orb) {
    for (const auto& [w, a] : v) {
      auto it = index.find(w);
      if (it == index.end()) continue;
      for (const auto& [kf, b] : it->second) {
        DatabaseScore& s = acc[kf];
        s.keyframe = kf;
        const double term = 0.5 * (std::fabs(a) + std::fabs(b) - std::fabs(a - b));
        (orb ? s.orb : s.lbd) += term;
        ++s.shared_words;
      }
    }
  };
  visit(orb_index_, q.orb, true);
  visit(lbd_index_, q.lbd, false);
  std::vector<DatabaseScore> out;
  out.reserve(acc.size());
  for (auto& [id, s] : acc) out.push_back(s);
  return out;
}

}  // namespace plslam
