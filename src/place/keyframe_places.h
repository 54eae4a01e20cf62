// The tracker's index of keyframes by appearance: each keyframe's bags of words (for place
// queries over the whole map, DBoW2's inverted index) and its descriptors' matching nodes
// (place/vocabulary_matching.h). Relocalisation asks it which keyframes look most like a
// frame; the reference-keyframe fallback matches through the stored nodes.
//
// Thread safety: none; the tracker owns it and uses it from its thread.
#pragma once

#include <memory>
#include <unordered_map>
#include <vector>

#include "core/map.h"
#include "place/keyframe_database.h"
#include "place/vocabulary_matching.h"

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindTrackerOptions (frontend/option_keys.cpp). `plslam run --print-config` lists them.
struct PlaceQueryOptions {
  int max_candidates = 5;
  double min_relative_score = 0.5;
  double point_weight = 0.6;
  double line_weight = 0.4;
};

/// A keyframe and how much it looks like the query (0..1).
struct PlaceScore {
  Id keyframe = kNoId;
  double score = 0;
};

class KeyframePlaces {
 public:
  /// Without a vocabulary (null or empty) the index stays empty and enabled() is false.
  explicit KeyframePlaces(std::shared_ptr<const VocabularySet> vocabulary);
  bool enabled() const { return vocabulary_ != nullptr; }

  /// The words of a frame (requires enabled()).
  FrameWords describe(const FrameFeatures& features) const;
  /// Stores (or replaces) keyframe `id`'s words.
  void add(Id id, const FrameFeatures& features);
  /// The same with words already described (describe()).
  void add(Id id, FrameWords words);
  /// A stored keyframe's words; null when unknown.
  const FrameWords* words(Id id) const;
  size_t size() const { return words_.size(); }

  /// Stored keyframes sharing words with `frame`, most similar first.
  std::vector<PlaceScore> query(const FrameWords& frame, const PlaceQueryOptions& options) const;

 private:
  std::shared_ptr<const VocabularySet> vocabulary_;
  KeyframeDatabase database_;
  std::unordered_map<Id, FrameWords> words_;
};

}  // namespace plslam
