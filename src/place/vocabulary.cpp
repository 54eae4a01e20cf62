#include "place/vocabulary.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <numeric>
#include <random>
#include <set>

#include "core/atomic_file.h"
#include "core/crc32.h"
#include "core/error.h"
#include "core/log.h"

#ifndef PLSLAM_VOCAB_DIR
#define PLSLAM_VOCAB_DIR "vocab"
#endif

namespace plslam {

namespace {

const Logger kLog("loop");
constexpr char kMagic[8] = {'P', 'L', 'S', 'L', 'V', 'O', 'C', '\0'};
constexpr uint32_t kVersion = 1;

using Descriptor = Vocabulary::Descriptor;

inline int hamming(const Descriptor& a, const uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 4; ++i) {
    uint64_t x, y;
    std::memcpy(&x, a.data() + 8 * i, 8);
    std::memcpy(&y, b + 8 * i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

Descriptor majority(const std::vector<Descriptor>& all, const std::vector<int>& members) {
  std::array<int, 256> counts{};
  for (int m : members)
    for (int byte = 0; byte < 32; ++byte)
      for (int bit = 0; bit < 8; ++bit) counts[byte * 8 + bit] += (all[m][byte] >> (7 - bit)) & 1;
  Descriptor c{};
  const int n = static_cast<int>(members.size());
  for (int byte = 0; byte < 32; ++byte)
    for (int bit = 0; bit < 8; ++bit)
      if (2 * counts[byte * 8 + bit] > n) c[byte] |= static_cast<uint8_t>(1u << (7 - bit));
  return c;
}

/// k-majority clustering of `members` (indices into `all`); returns the non-empty clusters.
std::vector<std::vector<int>> kMajority(const std::vector<Descriptor>& all, const std::vector<int>& members, int k,
                                        int iterations, std::mt19937_64* rng) {
  // k-means++ seeding.
  std::vector<Descriptor> centres;
  std::vector<double> d2(members.size(), std::numeric_limits<double>::max());
  centres.push_back(all[members[(*rng)() % members.size()]]);
  while (static_cast<int>(centres.size()) < k) {
    double total = 0;
    for (size_t i = 0; i < members.size(); ++i) {
      const double d = hamming(centres.back(), all[members[i]].data());
      d2[i] = std::min(d2[i], d * d);
      total += d2[i];
    }
    if (total <= 0) break;  // fewer distinct descriptors than k
    double r = std::uniform_real_distribution<double>(0, total)(*rng);
    size_t pick = 0;
    for (; pick + 1 < members.size(); ++pick) {
      r -= d2[pick];
      if (r <= 0) break;
    }
    centres.push_back(all[members[pick]]);
  }
  std::vector<int> assign(members.size(), -1);
  std::vector<std::vector<int>> clusters;
  for (int it = 0; it < iterations; ++it) {
    bool changed = false;
    for (size_t i = 0; i < members.size(); ++i) {
      int best = 0, best_d = 257;
      for (size_t c = 0; c < centres.size(); ++c) {
        const int d = hamming(centres[c], all[members[i]].data());
        if (d < best_d) best_d = d, best = static_cast<int>(c);
      }
      if (assign[i] != best) assign[i] = best, changed = true;
    }
    clusters.assign(centres.size(), {});
    for (size_t i = 0; i < members.size(); ++i) clusters[assign[i]].push_back(members[i]);
    if (!changed && it > 0) break;
    for (size_t c = 0; c < centres.size(); ++c)
      if (!clusters[c].empty()) centres[c] = majority(all, clusters[c]);
  }
  clusters.erase(std::remove_if(clusters.begin(), clusters.end(), [](const auto& c) { return c.empty(); }),
                 clusters.end());
  return clusters;
}

void put32(std::vector<uint8_t>* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}
uint32_t get32(const std::vector<uint8_t>& d, size_t* pos, const std::string& source) {
  if (*pos + 4 > d.size()) throw DataError(source + ": vocabulary file truncated (corrupt)");
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(d[*pos + i]) << (8 * i);
  *pos += 4;
  return v;
}

/// Every descriptor row of every image, with the image it came from.
void collectDescriptors(const std::vector<cv::Mat>& images, std::vector<Descriptor>* all, std::vector<int>* image_of) {
  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& m = images[i];
    if (m.empty()) continue;
    if (m.type() != CV_8U || m.cols != 32) throw DataError(str("vocabulary training: image ", i, " has descriptors that are not 32-byte CV_8U rows"));
    for (int r = 0; r < m.rows; ++r) {
      Descriptor d;
      std::memcpy(d.data(), m.ptr<uint8_t>(r), 32);
      all->push_back(d);
      image_of->push_back(static_cast<int>(i));
    }
  }
  if (all->empty()) throw DataError("vocabulary training: no descriptors");
}

/// Per word ln(N / images containing it) (at least one image counted).
std::vector<float> idfWeights(const std::vector<std::set<int>>& images_of_word, size_t image_count) {
  const double n_images = static_cast<double>(image_count);
  std::vector<float> idf(images_of_word.size());
  for (size_t w = 0; w < images_of_word.size(); ++w) {
    const double ni = std::max<size_t>(1, images_of_word[w].size());
    idf[w] = static_cast<float>(std::log(n_images / ni));
  }
  return idf;
}

}  // namespace

double bowScore(const BowVector& a, const BowVector& b) {
  // 0.5 * sum over common words of (|a| + |b| - |a - b|) = 1 - 0.5 |a - b|_1 for unit vectors.
  double s = 0;
  auto ia = a.begin(), ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) ++ia;
    else if (ib->first < ia->first) ++ib;
    else {
      s += std::fabs(ia->second) + std::fabs(ib->second) - std::fabs(ia->second - ib->second);
      ++ia, ++ib;
    }
  }
  return 0.5 * s;
}

Vocabulary Vocabulary::train(const std::vector<cv::Mat>& images, const VocabularyTrainOptions& options) {
  if (options.k < 2 || options.levels < 1 || options.iterations < 1)
    throw ConfigError(str("vocabulary training: k must be >= 2, levels and iterations >= 1 (k ", options.k,
                          ", levels ", options.levels, ")"));
  std::vector<Descriptor> all;
  std::vector<int> image_of;
  collectDescriptors(images, &all, &image_of);

  Vocabulary v;
  v.k_ = options.k;
  v.levels_ = options.levels;
  v.training_images_ = static_cast<int>(images.size());
  std::mt19937_64 rng(options.seed);
  Node root;
  v.nodes_.push_back(root);
  // Depth-first: all children of a node are created together, then each is split in turn,
  // so nodes are stored parent first with siblings contiguous.
  struct Task {
    int node, level;
    std::vector<int> members;
  };
  std::vector<Task> stack;
  std::vector<int> everyone(all.size());
  std::iota(everyone.begin(), everyone.end(), 0);
  stack.push_back({0, 0, std::move(everyone)});
  std::vector<std::vector<int>> leaf_members;  // per node (filled for leaves)
  leaf_members.resize(1);
  while (!stack.empty()) {
    Task t = std::move(stack.back());
    stack.pop_back();
    if (t.level >= options.levels || static_cast<int>(t.members.size()) <= 1) {
      leaf_members[t.node] = std::move(t.members);
      continue;
    }
    std::vector<std::vector<int>> clusters;
    if (static_cast<int>(t.members.size()) <= options.k) {
      for (int m : t.members) clusters.push_back({m});
    } else {
      clusters = kMajority(all, t.members, options.k, options.iterations, &rng);
    }
    if (clusters.size() <= 1) {  // identical descriptors: cannot split further
      leaf_members[t.node] = std::move(t.members);
      continue;
    }
    const int first = static_cast<int>(v.nodes_.size());
    for (const auto& c : clusters) {
      Node n;
      n.parent = t.node;
      n.centre = majority(all, c);
      v.nodes_.push_back(n);
      leaf_members.emplace_back();
    }
    for (int c = static_cast<int>(clusters.size()) - 1; c >= 0; --c)
      stack.push_back({first + c, t.level + 1, std::move(clusters[c])});
  }
  v.finalise();
  // idf: ln(N / images containing the word), from the training assignment.
  std::vector<std::set<int>> images_of_word(v.word_nodes_.size());
  for (size_t n = 0; n < v.nodes_.size(); ++n)
    if (v.nodes_[n].word >= 0)
      for (int m : leaf_members[n]) images_of_word[v.nodes_[n].word].insert(image_of[m]);
  const std::vector<float> idf = idfWeights(images_of_word, images.size());
  for (size_t w = 0; w < v.word_nodes_.size(); ++w) v.nodes_[v.word_nodes_[w]].weight = idf[w];
  kLog.info(str("vocabulary trained: ", all.size(), " descriptors of ", images.size(), " images, ", v.words(),
                " words (k ", options.k, ", levels ", options.levels, ")"));
  return v;
}

void Vocabulary::finalise() {
  word_nodes_.clear();
  for (Node& n : nodes_) n.children.clear(), n.word = -1;
  for (size_t i = 1; i < nodes_.size(); ++i) nodes_[nodes_[i].parent].children.push_back(static_cast<int>(i));
  for (size_t i = 0; i < nodes_.size(); ++i) {
    if (nodes_[i].children.empty()) {
      nodes_[i].word = static_cast<int>(word_nodes_.size());
      word_nodes_.push_back(static_cast<int>(i));
    }
  }
}

int Vocabulary::word(const uint8_t* d, int node_depth, int* node) const {
  if (node) *node = -1;
  if (nodes_.empty()) return -1;
  int n = 0;
  for (int depth = 0; !nodes_[n].children.empty(); ++depth) {
    if (node && depth == node_depth) *node = n;
    int best = nodes_[n].children.front(), best_d = 257;
    for (int c : nodes_[n].children) {
      const int dist = hamming(nodes_[c].centre, d);
      if (dist < best_d) best_d = dist, best = c;
    }
    n = best;
  }
  if (node && *node < 0) *node = n;
  return nodes_[n].word;
}

float Vocabulary::weight(int w) const {
  return w >= 0 && w < words() ? nodes_[word_nodes_[w]].weight : 0.f;
}

BowVector Vocabulary::transform(const cv::Mat& descriptors, std::vector<int>* words) const {
  BowVector out;
  if (words) words->clear();
  if (descriptors.empty() || nodes_.empty()) return out;
  if (descriptors.type() != CV_8U || descriptors.cols != 32)
    throw DataError("Vocabulary::transform: descriptors must be 32-byte CV_8U rows");
  std::vector<int> ws(descriptors.rows);
  for (int r = 0; r < descriptors.rows; ++r) ws[r] = word(descriptors.ptr<uint8_t>(r));
  std::vector<int> sorted = ws;
  std::sort(sorted.begin(), sorted.end());
  double total = 0;
  for (size_t i = 0; i < sorted.size();) {
    size_t j = i;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    const float value = static_cast<float>((j - i)) * weight(sorted[i]);  // tf (normalised below) * idf
    if (value > 0) {
      out.emplace_back(sorted[i], value);
      total += value;
    }
    i = j;
  }
  if (total > 0)
    for (auto& [w, v] : out) v = static_cast<float>(v / total);
  if (words) *words = std::move(ws);
  return out;
}

void Vocabulary::writeTree(std::vector<uint8_t>* out) const {
  put32(out, static_cast<uint32_t>(k_));
  put32(out, static_cast<uint32_t>(levels_));
  put32(out, static_cast<uint32_t>(training_images_));
  put32(out, static_cast<uint32_t>(nodes_.size()));
  for (const Node& n : nodes_) {
    put32(out, static_cast<uint32_t>(n.parent));
    out->insert(out->end(), n.centre.begin(), n.centre.end());
    uint32_t w;
    std::memcpy(&w, &n.weight, 4);
    put32(out, w);
  }
}

Vocabulary Vocabulary::readTree(const std::vector<uint8_t>& d, size_t* pos, const std::string& source) {
  Vocabulary v;
  v.k_ = static_cast<int>(get32(d, pos, source));
  v.levels_ = static_cast<int>(get32(d, pos, source));
  v.training_images_ = static_cast<int>(get32(d, pos, source));
  const uint32_t count = get32(d, pos, source);
  if (v.k_ < 2 || v.levels_ < 1 || count == 0 || count > (d.size() - *pos) / 40)
    throw DataError(str(source, ": vocabulary tree header is inconsistent (k ", v.k_, ", levels ", v.levels_, ", nodes ",
                        count, "): corrupt file"));
  v.nodes_.resize(count);
  for (uint32_t i = 0; i < count; ++i) {
    Node& n = v.nodes_[i];
    n.parent = static_cast<int32_t>(get32(d, pos, source));
    if ((i == 0) != (n.parent == -1) || n.parent >= static_cast<int>(i))
      throw DataError(str(source, ": vocabulary node ", i, " has parent ", n.parent, " (must precede it): corrupt file"));
    std::memcpy(n.centre.data(), d.data() + *pos, 32);
    *pos += 32;
    const uint32_t w = get32(d, pos, source);
    std::memcpy(&n.weight, &w, 4);
  }
  v.finalise();
  return v;
}

bool Vocabulary::operator==(const Vocabulary& o) const {
  if (k_ != o.k_ || levels_ != o.levels_ || training_images_ != o.training_images_ || nodes_.size() != o.nodes_.size())
    return false;
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].parent != o.nodes_[i].parent || nodes_[i].centre != o.nodes_[i].centre ||
        nodes_[i].weight != o.nodes_[i].weight)
      return false;
  return true;
}

void saveVocabulary(const std::string& path, const VocabularySet& vocabulary) {
  std::vector<uint8_t> out(kMagic, kMagic + 8);
  put32(&out, kVersion);
  put32(&out, 2);
  put32(&out, 0);
  vocabulary.orb.writeTree(&out);
  put32(&out, 1);
  vocabulary.lbd.writeTree(&out);
  put32(&out, crc32(out.data(), out.size()));
  writeFileAtomically(path, std::string(out.begin(), out.end()));
}

VocabularySet loadVocabulary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the vocabulary file");
  std::vector<uint8_t> d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (d.size() < 8 + 4 + 4 + 4 || std::memcmp(d.data(), kMagic, 8) != 0)
    throw DataError(path + ": not a plslam vocabulary file (bad magic): corrupt or wrong file");
  uint32_t stored = 0;
  for (int i = 0; i < 4; ++i) stored |= static_cast<uint32_t>(d[d.size() - 4 + i]) << (8 * i);
  size_t pos = 8;
  const uint32_t version = get32(d, &pos, path);
  if (version != kVersion)
    throw DataError(str(path, ": vocabulary file version ", version, ", this build reads version ", kVersion));
  if (crc32(d.data(), d.size() - 4) != stored)
    throw DataError(path + ": vocabulary file CRC mismatch: the file is corrupt (truncated or altered)");
  const std::vector<uint8_t> body(d.begin(), d.end() - 4);
  const uint32_t trees = get32(body, &pos, path);
  VocabularySet set;
  bool have_orb = false, have_lbd = false;
  for (uint32_t t = 0; t < trees; ++t) {
    const uint32_t type = get32(body, &pos, path);
    if (type == 0) set.orb = Vocabulary::readTree(body, &pos, path), have_orb = true;
    else if (type == 1) set.lbd = Vocabulary::readTree(body, &pos, path), have_lbd = true;
    else throw DataError(str(path, ": unknown vocabulary tree type ", type, ": corrupt file"));
  }
  if (!have_orb || !have_lbd || pos != body.size())
    throw DataError(path + ": vocabulary file lacks the ORB or LBD tree or has trailing bytes: corrupt file");
  return set;
}

std::string defaultVocabularyPath() { return std::string(PLSLAM_VOCAB_DIR) + "/plslam_orb_lbd.voc"; }

}  // namespace plslam
