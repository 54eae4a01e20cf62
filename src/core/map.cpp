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
  next_keyframe_id_ = other.next_keyframe_id_;
  next_point_id_ = other.next_point_id_;
  next_line_id_ = other.next_line_id_;
  corrections_ = other.corrections_;
  other.keyframes_.clear();
  other.points_.clear();
  other.lines_.clear();
  other.next_keyframe_id_ = other.next_point_id_ = other.next_line_id_ = 0;
  return *this;
}

namespace {
template <typename T>
Id restoreInto(std::map<Id, T>* entities, Id* next_id, T entity, const char* what) {
  const Id id = entity.id;
  if (id < 0) throw DataError(std::string("Map: cannot restore a ") + what + " with id " + std::to_string(id));
  if (entities->count(id)) throw DataError(std::string("Map: ") + what + " id " + std::to_string(id) + " restored twice");
  entities->emplace(id, std::move(entity));
  *next_id = std::max(*next_id, id + 1);
  return id;
}
}  // namespace

Id Map::restoreKeyFrame(KeyFrame kf) { return restoreInto(&keyframes_, &next_keyframe_id_, std::move(kf), "keyframe"); }
Id Map::restorePoint(MapPoint p) { return restoreInto(&points_, &next_point_id_, std::move(p), "map point"); }
Id Map::restoreLine(MapLine l) { return restoreInto(&lines_, &next_line_id_, std::move(l), "map line"); }

Id Map::addKeyFrame(KeyFrame kf) {
  kf.id = next_keyframe_id_++;
  kf.point_ids.resize(kf.features.points.size(), kNoId);
  kf.line_ids.resize(kf.features.lines.size(), kNoId);
  const Id id = kf.id;
  keyframes_.emplace(id, std::move(kf));
  return id;
}

Id Map::addPoint(MapPoint p) {
  p.id = next_point_id_++;
  const Id id = p.id;
  points_.emplace(id, std::move(p));
  return id;
}

Id Map::addLine(MapLine l) {
  l.id = next_line_id_++;
  const Id id = l.id;
  lines_.emplace(id, std::move(l));
  return id;
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
  points_.erase(it);
}

void Map::eraseLine(Id ln) {
  auto it = lines_.find(ln);
  if (it == lines_.end()) return;
  for (const auto& [kf, idx] : it->second.observations)
    if (KeyFrame* k = keyframe(kf); k && k->line_ids[idx] == ln) k->line_ids[idx] = kNoId;
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

KeyFrame* Map::keyframe(Id id) {
  auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : &it->second;
}
MapPoint* Map::point(Id id) {
  auto it = points_.find(id);
  return it == points_.end() ? nullptr : &it->second;
}
MapLine* Map::line(Id id) {
  auto it = lines_.find(id);
  return it == lines_.end() ? nullptr : &it->second;
}
const KeyFrame* Map::keyframe(Id id) const { return const_cast<Map*>(this)->keyframe(id); }
const MapPoint* Map::point(Id id) const { return const_cast<Map*>(this)->point(id); }
const MapLine* Map::line(Id id) const { return const_cast<Map*>(this)->line(id); }

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
