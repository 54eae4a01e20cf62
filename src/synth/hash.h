// Counter-based hashing for the synthetic scenes: every random choice (texture layout,
// noise of pixel (x, y) in frame i) is a pure function of the seed and its coordinates,
// so a frame renders the same whatever was rendered before it, in any order or thread.
#pragma once

#include <cstdint>

namespace plslam::synth {

/// SplitMix64 finaliser: a good 64-bit mixer.
inline uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

inline uint64_t hash2(uint64_t a, uint64_t b) { return mix64(a * 0x9E3779B97F4A7C15ULL + mix64(b + 0x632BE59BD9B4E019ULL)); }
inline uint64_t hash3(uint64_t a, uint64_t b, uint64_t c) { return hash2(hash2(a, b), c); }

/// Uniform in [0, 1) from the top 53 bits.
inline double unitFromHash(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace plslam::synth
