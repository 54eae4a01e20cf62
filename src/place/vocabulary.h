// Bag of binary words (DBoW2 style) for place recognition.
//
// A vocabulary is a tree of k-majority clusters: descriptors are split into k groups with
// k-means++ seeding and Hamming distance, each group's centre is the bitwise majority of its
// members, recursively for `levels` levels; the leaves are the words. Each word carries an
// idf weight ln(N / n_w) (N training images, n_w of them containing the word). An image
// becomes a sparse tf-idf vector normalised to unit L1 norm; two vectors score
// s = 1 - 0.5 |a - b|_1 in [0, 1] (DBoW2's L1 score).
//
// One tree per descriptor type, both in one file (VocabularySet): ORB (rBRIEF on corners)
// and LBD (bands across a segment) are 32-byte strings of unrelated meaning, so clustering
// them jointly would only mix two unrelated distributions in the upper nodes and let one
// type crowd the other out of the words; separate trees keep each type's words and idf
// statistics its own, and the loop detector combines the two scores with explicit weights.
//
// File format (little endian): "PLSLVOC\0", uint32 version (1), uint32 tree count, per
// tree: uint32 type (0 ORB, 1 LBD), uint32 k, uint32 levels, uint32 training images,
// uint32 node count, then per node: int32 parent (-1 root), 32 descriptor bytes, float32
// idf weight (0 for inner nodes); finally a CRC-32 (zlib polynomial) of all preceding
// bytes. Nodes are stored parent before child, children in order.
//
// Thread safety: a built or loaded vocabulary is immutable; transform() may run concurrently.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

namespace plslam {

/// Sparse bag-of-words vector: (word id, weight), sorted by word id, L1 norm 1 (or empty).
using BowVector = std::vector<std::pair<int, float>>;

/// DBoW2 L1 score of two normalised vectors: 1 - 0.5 * |a - b|_1, in [0, 1].
double bowScore(const BowVector& a, const BowVector& b);

struct VocabularyTrainOptions {
  int k = 10;             ///< branching factor
  int levels = 4;         ///< depth of the tree (words <= k^levels)
  int iterations = 10;    ///< k-majority iterations per split
  uint64_t seed = 1;      ///< k-means++ seeding (training is deterministic for a seed)
};

class Vocabulary {
 public:
  using Descriptor = std::array<uint8_t, 32>;

  /// Trains on descriptors grouped by image (CV_8U rows of 32 bytes, one Mat per image;
  /// empty Mats allowed). Throws ConfigError for k < 2 or levels < 1, DataError for
  /// descriptors that are not 32-byte CV_8U rows or when there are none at all.
  static Vocabulary train(const std::vector<cv::Mat>& images, const VocabularyTrainOptions& options);

  bool empty() const { return nodes_.empty(); }
  int k() const { return k_; }
  int levels() const { return levels_; }
  int words() const { return static_cast<int>(word_nodes_.size()); }
  int trainingImages() const { return training_images_; }

  /// The word of one 32-byte descriptor (descending the tree by Hamming distance); -1 when empty.
  /// `node` (optional) gets the node passed through `node_depth` levels below the root (the
  /// leaf when the tree is shallower): descriptors under one node are near each other, which
  /// is what matching through the vocabulary groups by (place/vocabulary_matching.h).
  int word(const uint8_t* descriptor, int node_depth = 0, int* node = nullptr) const;
  /// tf-idf vector of an image's descriptors (rows of CV_8U, 32 columns), L1-normalised.
  /// `words` (optional) gets each row's word.
  BowVector transform(const cv::Mat& descriptors, std::vector<int>* words = nullptr) const;
  /// The idf weight of a word.
  float weight(int word) const;

  /// Serialisation of one tree (the body of the file format above, without header and CRC).
  void writeTree(std::vector<uint8_t>* out) const;
  /// Reads one tree at `*pos` of `data`; throws DataError naming `source` when truncated or inconsistent.
  static Vocabulary readTree(const std::vector<uint8_t>& data, size_t* pos, const std::string& source);

  bool operator==(const Vocabulary& o) const;

 private:
  struct Node {
    int parent = -1;
    Descriptor centre{};
    float weight = 0;      ///< idf for words, 0 for inner nodes
    std::vector<int> children;
    int word = -1;         ///< word id of a leaf
  };
  void finalise();  // children lists and word ids from parents
  std::vector<Node> nodes_;
  std::vector<int> word_nodes_;
  int k_ = 0, levels_ = 0, training_images_ = 0;
};

/// The ORB and LBD trees of one vocabulary file.
struct VocabularySet {
  Vocabulary orb;
  Vocabulary lbd;
};

/// Writes the file format above atomically. Throws IoError naming the file.
void saveVocabulary(const std::string& path, const VocabularySet& vocabulary);
/// Reads and checks a vocabulary file. Throws IoError when missing or unreadable, DataError
/// naming the file when the magic, version, CRC or structure is wrong ("corrupt").
VocabularySet loadVocabulary(const std::string& path);

/// The vocabulary shipped with the sources (vocab/plslam_orb_lbd.voc in the source tree).
std::string defaultVocabularyPath();

}  // namespace plslam
