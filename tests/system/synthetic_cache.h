// Synthetic sequences shared by the system tests: rendered once into the temp folder and
// reused by later test processes (a lock file serialises the first render).
#pragma once

#include <string>
#include <vector>

#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam::test {

/// The folder of a rendered synthetic sequence (TUM layout with groundtruth.txt and camera.xml).
std::string syntheticSequence(synth::SceneKind kind, int frames);

/// A synthetic scene rendered in memory (no files), frames in order.
struct RenderedSequence {
  synth::Scene scene;
  std::vector<synth::RenderedFrame> frames;
};
/// Renders every frame of a `kind` scene with `options`, on two threads.
RenderedSequence renderSequence(synth::SceneKind kind, const synth::SceneOptions& options);

}  // namespace plslam::test
