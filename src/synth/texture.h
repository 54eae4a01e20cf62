// Procedural, seeded face textures for the synthetic scenes.
//
// A face is filled with a random rectangle subdivision (a "Mondrian"): recursive splits
// at hashed positions, some split lines drawn as dark grout, each leaf a plain colour or
// one of a few printed-looking patterns (stripes, diagonal stripes, a framed poster,
// rows of text-like blocks, a random two-colour tile code). This gives many corners
// (for ORB) and long straight edges at several orientations (for LSD) without the
// repetition of a checkerboard. Everything is a pure function of (seed, position).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plslam::synth {

/// What a face looks like: the palette and the sizes of its texture elements.
enum class Material : uint8_t {
  kWall,       ///< painted wall with posters, frames and notes
  kFloor,      ///< wooden planks / tiles
  kCeiling,    ///< pale panels
  kWood,       ///< furniture
  kCardboard,  ///< boxes with printed labels
  kPoster,     ///< fine, colourful print (pictures on the walls)
  kShirt,      ///< a person's upper body (hue from the seed)
  kTrousers,   ///< a person's legs
  kSkin,       ///< a person's face
  kHair,       ///< top and back of a person's head
};

const char* materialName(Material m);

struct Rgb {
  float r = 0, g = 0, b = 0;  ///< linear 0..1
};

/// The texture of one face: the subdivision is built once (a few thousand nodes at most),
/// with a coarse grid that gives each lookup the deepest node its grid cell lies in, so a
/// lookup is a short walk down a tree of comparisons. Immutable after construction.
class FaceTexture {
 public:
  FaceTexture(Material m, uint64_t seed, double w, double h);
  /// Colour at (s, t) metres from the face's corner.
  Rgb colour(double s, double t) const;
  /// The same colour by the full walk from the root, without the grid (a reference for tests).
  Rgb colourFromRoot(double s, double t) const;
  size_t leafCount() const { return leaves_.size(); }

  struct Node {
    double pos = 0;        ///< split position (s if split_x, else t)
    int child = -1;        ///< first child (the second is child + 1); -1: a leaf
    int leaf = -1;         ///< index into leaves_ when a leaf
    bool split_x = false;  ///< split along s
    bool grout = false;    ///< the split line is drawn
  };
  struct Leaf {
    double x0, x1, y0, y1;  ///< rectangle
    uint64_t hash;
    Rgb c0, c1;             ///< palette
    bool plain;             ///< one flat colour (c0)
  };

 private:
  void build(int index, double x0, double x1, double y0, double y1, uint64_t node, int depth);
  void buildGrid(double w, double h);
  Rgb walk(int start, double s, double t) const;
  Material material_;
  uint64_t base_;
  double seed_hue_;
  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
  double half_grout_ = 0;
  double cell_inv_ = 1;      ///< 1 / grid cell size
  int grid_w_ = 1, grid_h_ = 1;
  std::vector<int> grid_;    ///< start node per cell, row-major
};

}  // namespace plslam::synth
