// The servo's simulated world as a camera sees it: the synthetic room of synth/ (the
// static layout, no moving objects) with one tag36h11 AprilTag flat on a wall, rendered
// from any camera pose. The tag is drawn over the rendered colour image where its plane is
// the surface the pixel sees (so furniture in front of it hides it); depth is the wall's.
//
// Frames: the room frame is synth's world (z up, floor at z = 0, x in [-3, 3], y in
// [-2.5, 2.5]). The tag frame is calibration's target frame of a single tag: origin at the
// tag centre, x to the right as printed, y down, z into the wall.
//
// Thread safety: render() is const and thread-safe.
#pragma once

#include <cstdint>

#include "calibration/target.h"
#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {

struct TagRoomOptions {
  int width = 320;         ///< image size, pixels (synth's camera: fx = 525 * width / 640)
  int height = 240;
  int tag_id = 0;          ///< tag36h11 id
  double tag_size = 0.25;  ///< edge of the tag's black border, metres
  uint64_t seed = 1;       ///< textures and sensor noise of the room
};

class TagRoom {
 public:
  /// T_room_tag: the tag frame in the room; the tag must lie on a wall for its depth to be right.
  TagRoom(const SE3& T_room_tag, const TagRoomOptions& options = {});

  /// The tag centred at (y, z) on the east wall (x = 3), facing into the room (-x).
  static SE3 onEastWall(double y, double z);

  /// The view from T_room_c at time t; `noise_stream` selects the sensor noise pattern.
  synth::RenderedFrame render(const SE3& T_room_c, TimeNs t_ns, uint64_t noise_stream) const;

  const PinholeCamera& camera() const { return scene_.camera(); }
  const calib::Target& target() const { return target_; }
  const SE3& tagPose() const { return T_room_tag_; }
  const TagRoomOptions& options() const { return options_; }

 private:
  TagRoomOptions options_;
  synth::Scene scene_;
  calib::Target target_;
  SE3 T_room_tag_;
  /// Draws the printed tag into frame->bgr where the pixel's ray meets its printed area at
  /// the depth the frame has there (or has none).
  void drawTag(const SE3& T_room_c, synth::RenderedFrame* frame) const;
};

}  // namespace plslam
