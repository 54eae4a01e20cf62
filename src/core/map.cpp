#include "core/map.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace plslam {

Map::Map(Map&& other) noexcept { *this = std::move(other); }

Map& Map::operator=(Map&& other) noexcept {
  if (this == &other) return *this;
  keyframes_ = std::move(other.keyframes_);
  points_ = std::move(other.points_);
  lines_ = std::move(other.lines_);
  keyframe_at_ = std::move(other.keyframe_at_);
  point_at_ = std::move(other.point_at_);
  line_at_ = std::move(other.line_at_);
  next_keyframe_id_ = other.next_keyframe_id_;
  next_point_id_ = other.next_point_id_;
  next_line_id_ = other.next_line_id_;
  corrections_ = other.corrections_;
  other.keyframes_.clear();
  other.points_.clear();
  other.lines_.clear();
  other.keyframe_at_.clear();
  other.point_at_.clear();
  other.line_at_.clear();
  other.next_keyframe_id_ = other.next_point_id_ = other.next_line_id_ = 0;
  return *this;
}

namespace {

/// Stores `entity` under its id (not in use, >= 0) and indexes it.
template <typename T>
Id insertEntity(std::map<Id, T>* entities, std::vector<T*>* at, T entity) {
  const Id id = entity.id;
  T* stored = &entities->emplace(id, std::move(entity)).first->second;
  if (static_cast<Id>(at->size()) <= id) at->resize(static_cast<size_t>(id) + 1, nullptr);
  (*at)[static_cast<size_t>(id)] = stored;
  return id;
}

template <typename T>
Id restoreInto(std::map<Id, T>* entities, std::vector<T*>* at, Id* next_id, T entity, const char* what) {
  const Id id = entity.id;
  if (id < 0) throw DataError(std::string("Map: cannot restore a ") + what + " with id " + std::to_string(id));
  if (entities->count(id)) throw DataError(std::string("Map: ") + what + " id " + std::to_string(id) + " restored twice");
  *next_id = std::max(*next_id, id + 1);
  return insertEntity(entities, at, std::move(entity));
}

}  // namespace

Id Map::restoreKeyFrame(KeyFrame kf) {
  return restoreInto(&keyframes_, &keyframe_at_, &next_keyframe_id_, std::move(kf), "keyframe");
}
Id Map::restorePoint(MapPoint p) {
  return restoreInto(&points_, &point_at_, &next_point_id_, std::move(p), "map point");
}
Id Map::restoreLine(MapLine l) { return restoreInto(&lines_, &line_at_, &next_line_id_, std::move(l), "map line"); }

Id Map::addKeyFrame(KeyFrame kf) {
  kf.id = next_keyframe_id_++;
  kf.point_ids.resize(kf.features.points.size(), kNoId);
  kf.line_ids.resize(kf.features.lines.size(), kNoId);
  return insertEntity(&keyframes_, &keyframe_at_, std::move(kf));
}

Id Map::addPoint(MapPoint p) {
  p.id = next_point_id_++;
  return insertEntity(&points_, &point_at_, std::move(p));
}

Id Map::addLine(MapLine l) {
  l.id = next_line_id_++;
  return insertEntity(&lines_, &line_at_, std::move(l));
}

void Map::addPointObservation(Id kf, int index, Id pt) {
  KeyFrame* k = keyframe(kf);
  MapPoint* p = point(pt);
  if (!k || !p || index < 0 || index >= static_cast<int>(k->point_ids.size())) return;
  if (k->point_ids[index] != kNoId && k->point_ids[index] != pt) {
    if (MapPoint* old = point(k->point_ids[index])) old->observations.erase(kf);
  }
  if (auto it = p->observations.find(kf); it != p->observations.end() && it->second != index) {
    k->point_ids[it->second] = kNoId;  // one keypoint per keyframe for a point
  }
  k->point_ids[index] = pt;
  p->observations[kf] = index;
}

void Map::addLineObservation(Id kf, int index, Id ln) {
  KeyFrame* k = keyframe(kf);
  MapLine* l = line(ln);
  if (!k || !l || index < 0 || index >= static_cast<int>(k->line_ids.size())) return;
  if (k->line_ids[index] != kNoId && k->line_ids[index] != ln) {
    if (MapLine* old = line(k->line_ids[index])) old->observations.erase(kf);
  }
  if (auto it = l->observations.find(kf); it != l->observations.end() && it->second != index) {
    k->line_ids[it->second] = kNoId;
  }
  k->line_ids[index] = ln;
  l->observations[kf] = index;
}

void Map::erasePoint(Id pt) {
  auto it = points_.find(pt);
  if (it == points_.end()) return;
  for (const auto& [kf, idx] : it->second.observations)
    if (KeyFrame* k = keyframe(kf); k && k->point_ids[idx] == pt) k->point_ids[idx] = kNoId;
  point_at_[static_cast<size_t>(pt)] = nullptr;
  points_.erase(it);
}

void Map::eraseLine(Id ln) {
  auto it = lines_.find(ln);
  if (it == lines_.end()) return;
  for (const auto& [kf, idx] : it->second.observations)
    if (KeyFrame* k = keyframe(kf); k && k->line_ids[idx] == ln) k->line_ids[idx] = kNoId;
  line_at_[static_cast<size_t>(ln)] = nullptr;
  lines_.erase(it);
}

void Map::mergePoint(Id from, Id into) {
  if (from == into) return;
  MapPoint* f = point(from);
  MapPoint* t = point(into);
  if (!f || !t) return;
  const std::map<Id, int> obs = f->observations;
  t->visible += f->visible;
  t->found += f->found;
  erasePoint(from);
  for (const auto& [kf, idx] : obs)
    if (!point(into)->observations.count(kf)) addPointObservation(kf, idx, into);
}

std::vector<std::pair<Id, int>> Map::covisible(Id kf, int min_shared) const {
  std::map<Id, int> shared;
  const KeyFrame* k = keyframe(kf);
  if (!k) return {};
  for (Id pt : k->point_ids) {
    if (pt == kNoId) continue;
    if (const MapPoint* p = point(pt))
      for (const auto& [other, idx] : p->observations)
        if (other != kf) ++shared[other];
  }
  std::vector<std::pair<Id, int>> out;
  for (const auto& [id, n] : shared)
    if (n >= min_shared) out.emplace_back(id, n);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  return out;
}

}  // namespace plslam
