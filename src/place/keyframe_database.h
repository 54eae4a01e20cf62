// Inverted-index keyframe database (DBoW2 style): per word, the keyframes whose bag of
// words holds it, so a query only visits keyframes sharing a word with it. Keeps one index
// per descriptor type (ORB, LBD); scores are DBoW2's L1 score (see vocabulary.h).
//
// Thread safety: none; the loop closer owns it and uses it from one thread.
#pragma once

#include <map>
#include <unordered_map>
#include <vector>

#include "core/frame.h"
#include "core/map.h"
#include "place/vocabulary.h"

namespace plslam {

/// A keyframe's bags of words.
struct KeyframeBow {
  BowVector orb;  ///< ORB words
  BowVector lbd;  ///< LBD words
};

/// Bags of words of one keyframe's features.
KeyframeBow describeBow(const VocabularySet& vocabulary, const FrameFeatures& features);

/// One keyframe's similarity to a query.
struct DatabaseScore {
  Id keyframe = kNoId;
  double orb = 0;  ///< L1 score of the ORB vectors
  double lbd = 0;  ///< L1 score of the LBD vectors
  int shared_words = 0;  ///< words (both types) in common
};

class KeyframeDatabase {
 public:
  /// Adds (or replaces) a keyframe.
  void add(Id keyframe, KeyframeBow bow);
  /// Removes a keyframe; unknown ids are ignored.
  void remove(Id keyframe);
  bool contains(Id keyframe) const { return bows_.count(keyframe) > 0; }
  const KeyframeBow* bow(Id keyframe) const;
  size_t size() const { return bows_.size(); }

  /// Every stored keyframe sharing at least one word with `query`, with its scores; in id order.
  std::vector<DatabaseScore> query(const KeyframeBow& query) const;

 private:
  using Index = std::unordered_map<int, std::vector<std::pair<Id, float>>>;
  static void addTo(Index* index, Id keyframe, const BowVector& v);
  static void removeFrom(Index* index, Id keyframe, const BowVector& v);
  std::map<Id, KeyframeBow> bows_;
  Index orb_index_, lbd_index_;
};

}  // namespace plslam
