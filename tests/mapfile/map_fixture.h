// A map built by a short sequential SLAM run on the cached synthetic static scene, shared by
// the mapfile tests (built once per test process), and a field-by-field map comparison.
#pragma once

#include <string>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "core/trajectory.h"

namespace plslam::test {

/// Frames of the synthetic sequence the map is built from.
constexpr int kMapFrames = 80;

struct BuiltMap {
  std::string dataset;       ///< the synthetic folder
  PinholeCamera camera;
  std::string config_yaml;   ///< the effective configuration (YAML)
  const Map* map = nullptr;  ///< after the run, with instances, a dense cloud and masks added
  Trajectory trajectory;     ///< the run's trajectory
  double ate = 0;            ///< its ATE RMSE against the ground truth
};
/// The shared map. Built by SLAM once and cached on disk (map file and trajectory in the
/// temp folder, like the synthetic sequences), so each test process does not run SLAM again.
const BuiltMap& builtMap();
/// The same map straight from a SLAM run in this process (no cache): for the round trip.
const BuiltMap& freshlyBuiltMap();

/// Every field of both maps equal (floats bit for bit, NaN equal to NaN).
void expectMapsEqual(const Map& a, const Map& b);

}  // namespace plslam::test
