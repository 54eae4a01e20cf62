// Synthetic sequences shared by the system tests: rendered once into the temp folder and
// reused by later test processes (a lock file serialises the first render).
#pragma once

#include <string>

#include "synth/scene.h"

namespace plslam::test {

/// The folder of a rendered synthetic sequence (TUM layout with groundtruth.txt and camera.xml).
std::string syntheticSequence(synth::SceneKind kind, int frames);

}  // namespace plslam::test
