// Shared truth for the calibration tests: a 640x480 camera with Brown distortion.
#pragma once

#include "camera/pinhole_camera.h"

namespace plslam::calib::test_fixtures {

inline PinholeCamera truthCamera() {
  PinholeCamera c;
  c.name = "truth";
  c.width = 640;
  c.height = 480;
  c.fx = 520.0;
  c.fy = 515.0;
  c.cx = 322.5;
  c.cy = 243.0;
  c.dist = {-0.12, 0.08, 0.0012, -0.0008, 0.0};
  c.depth_scale = 1000;
  return c;
}

}  // namespace plslam::calib::test_fixtures
