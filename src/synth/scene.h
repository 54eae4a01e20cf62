// Synthetic RGB-D scenes with exact ground truth: the geometry, the camera path and the
// moving objects of one scene. Rendering is in synth/renderer.h, files in synth/dataset.h.
//
// World frame: metres, z up, floor at z = 0; the room spans x in [-3, 3], y in [-2.5, 2.5],
// z in [0, 3]. Camera frame: x right, y down, z forward (OpenCV / TUM). Everything is made
// of boxes (axis-aligned or yawed; person limbs also pitch), so the scene's 3D corners and
// edges are known exactly.
//
// Scene kinds (the layout of furniture is the same in all of them):
//   static   hand-held camera looking at the shelf / table / cabinet corner, no moving objects
//   dynamic  the same camera path, two persons walking back and forth across the view
//            (one about 1 to 2 m in front of the camera, one farther off)
//   crowded  a slower camera; three persons walking in file 0.8 to 1 m in front of the
//            camera (more than half of the image is theirs for about 1 s each time they
//            pass, every 11 s from t = 1.5 s) and a fourth one farther away
//   loop     no moving objects; the camera goes once round an ellipse about the room centre
//            looking outward at the walls, and its last pose equals its first
//   loop_walkers  the loop's camera path; three persons walk in file 1 to 1.3 m in front
//            of the camera across the loop place (the first view, on the east wall) for
//            the first 2 s of the lap, covering much of the image, and have left the room
//            from t = 3 s (they vanish out of view): the loop place is occluded at the
//            first visit and clear at the return
//   fast     no moving objects; a hand-held camera that is slow for the first 1.2 s, then
//            alternates bursts of rotation (peaks of FastMotionOptions::max_rotation_deg_s)
//            and translation (up to about 1 m/s) with calm stretches; colour is motion
//            blurred over the exposure and its gain drifts and steps (synth/fast_motion.h)
// The seed changes the textures, the noise and the fast scene's exposure gain only;
// geometry and paths are fixed per kind.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "core/time.h"
#include "core/trajectory.h"
#include "synth/fast_motion.h"
#include "synth/texture.h"

namespace plslam::synth {

enum class SceneKind { kStatic, kDynamic, kLoop, kCrowded, kFast, kLoopWalkers };

/// "static", "dynamic", "loop", "crowded", "fast", "loop_walkers".
const char* sceneKindName(SceneKind kind);
/// The inverse of sceneKindName; throws ConfigError naming the accepted names.
SceneKind parseSceneKind(const std::string& name);
/// Frames that give the kind TUM-like speeds (loop and loop_walkers: one lap at about 0.35 m/s, 25 deg/s).
int defaultFrameCount(SceneKind kind);

/// Depth sensor imperfections (a Kinect-like model).
struct DepthNoiseOptions {
  bool enabled = true;              ///< false: exact depth (float metres), no dropouts, no colour noise
  double sigma_k = 0.002;           ///< depth noise sigma = sigma_k * z^2 (metres, z in metres)
  double quantum_m = 1.0 / 5000.0;  ///< depth values are rounded to this step (0: no rounding)
  double dropout_fraction = 0.003;  ///< fraction of random pixels with no reading
  double grazing_cos = 0.15;        ///< no reading where |cos(incidence)| is below this (about 81 deg)
  double edge_jump_m = 0.04;        ///< no reading on the far side of a depth jump larger than this (+2% of z)
  double min_depth_m = 0.4;         ///< no reading closer than this
  double max_depth_m = 8.0;         ///< no reading farther than this
  double colour_sigma = 1.0;        ///< Gaussian noise on the colour image, grey levels
};

/// The fast scene's camera path and camera effects (the other kinds ignore them).
struct FastMotionOptions {
  double max_rotation_deg_s = 180;  ///< peak rotation rate of the fastest bursts (sets the burst durations)
  bool motion_blur = true;          ///< colour integrates over the exposure (false: one instant, a sharp image)
  double exposure_ms = 12;          ///< exposure time, centred on the frame stamp (0..33)
  double blur_step_px = 1.5;        ///< the image moves at most this far between blur sub-frames...
  int max_subframes = 32;           ///< ...unless that needs more sub-frames than this
  bool gain = true;                 ///< exposure gain varying over time (false: constant 1)
};

struct SceneOptions {
  int frames = 300;            ///< number of frames, 30 Hz (loop: the laps span all of them)
  int laps = 1;                ///< loop scene: laps round the room over the frames (long-run tests)
  uint64_t seed = 1;           ///< textures and noise (not the geometry or the paths)
  int width = 640;             ///< image size; the focal length scales with the width (525 at 640)
  int height = 480;            ///< image height, pixels
  TimeNs start_ns = 1'600'000'000LL * kNsPerSecond;  ///< stamp of frame 0
  int aa_samples = 4;          ///< samples per pixel at colour edges (1 = no anti-aliasing; max 16)
  /// Adds copies of the shelf's two boxes and two books (same sizes and textures), without
  /// the shelf, on the floor by the south wall in another arrangement (placed through
  /// twinShelfTransform()): the same things laid out otherwise (loop-closure tests).
  bool twin_shelf = false;
  DepthNoiseOptions noise;     ///< depth and colour noise
  FastMotionOptions fast;      ///< fast scene only: path speed, motion blur, exposure gain
};

struct Segment3d {
  Eigen::Vector3d a, b;
};

/// A solid box: a pose, half sizes along its own axes, a material per face.
/// Faces are numbered axis * 2 + (0 for the -half side, 1 for the +half side).
struct Box {
  std::string name;
  SE3 T_w_b;                               ///< box frame (centre) in the world
  Eigen::Vector3d half_size{0.5, 0.5, 0.5};  ///< metres
  std::array<Material, 6> materials{};     ///< per face
  uint64_t texture_seed = 0;               ///< per box
  int instance_id = 0;                     ///< 0: static; >= 1: the moving object it belongs to
  bool inward = false;                     ///< the room: seen from inside

  std::array<Eigen::Vector3d, 8> corners() const;
  std::array<Segment3d, 12> edges() const;
  /// Signed distance to the box surface (negative inside the solid; for an inward box,
  /// negative outside the room).
  double signedDistance(const Eigen::Vector3d& p_w) const;
};

/// A moving object as it is listed in masks/instances.txt.
struct MovingObjectInfo {
  int instance_id = 0;     ///< >= 1, the value of its pixels in the instance masks
  int class_id = 0;        ///< COCO class id (0: person)
  std::string class_name;  ///< COCO class name
};

/// A person walking round a flat ellipse on the floor, facing where it goes, limbs swinging.
struct WalkPath {
  Eigen::Vector2d centre{0, 0};  ///< ellipse centre on the floor, metres
  double a = 1.5, b = 0.2;       ///< semi-axes along x and y, metres
  double period_s = 8.0;         ///< time of one round, seconds (negative: clockwise)
  double phase = 0.0;            ///< ellipse angle at t = 0, radians
  /// The person has left the room from this time on (seconds; infinity: never): no boxes,
  /// no mask pixels. Chosen by the scene at a time when the person is out of view.
  double leave_s = std::numeric_limits<double>::infinity();
};

/// The result of casting a ray into the scene.
struct RayHit {
  bool hit = false;
  double distance = 0;      ///< ray parameter: the point is origin + distance * dir
  Eigen::Vector3d point{0, 0, 0};
  Eigen::Vector3d normal{0, 0, 0};  ///< unit surface normal facing the ray
  int instance_id = 0;      ///< 0: static scenery
  int box = -1;             ///< index into boxesAt(t) (0 is the room)
  int face = -1;            ///< face of that box
};

class Scene {
 public:
  SceneKind kind() const { return kind_; }
  const SceneOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return camera_; }
  int frameCount() const { return options_.frames; }

  /// Stamp of frame i: start + i/30 s, rounded down to whole microseconds (so that TUM
  /// files with 6 decimals hold it exactly).
  TimeNs frameTime(int i) const;
  /// T_w_c at frame i / at any time (the paths are smooth functions of time).
  SE3 cameraPose(int i) const { return cameraPoseAt(frameTime(i)); }
  SE3 cameraPoseAt(TimeNs t_ns) const;
  /// One pose per frame, at the frame stamps.
  Trajectory groundTruth() const;

  /// Colour integrates over [t - e/2, t + e/2] around a frame's stamp t (depth, instance
  /// ids and the ground-truth pose are those at t); 0 means a single instant, no blur.
  /// Non-zero only for the fast scene with motion blur on.
  TimeNs exposureNs() const;
  /// Factor on the colour at time t (1 except for the fast scene with gain on).
  double exposureGain(TimeNs t_ns) const;

  /// The room (an inward box) and the furniture, in a fixed order.
  const Box& room() const { return static_boxes_.front(); }
  const std::vector<Box>& staticBoxes() const { return static_boxes_; }
  /// Corners / edges of all static boxes, the room's included (visibility is the caller's problem).
  std::vector<Eigen::Vector3d> staticCorners() const;
  std::vector<Segment3d> staticEdges() const;

  const std::vector<MovingObjectInfo>& movingObjects() const { return moving_info_; }
  /// The parts of the moving objects at time t (each carries its instance id; none of a
  /// person who has left, WalkPath::leave_s).
  std::vector<Box> movingBoxes(TimeNs t_ns) const;
  /// The static boxes followed by the moving ones at time t (RayHit::box indexes this).
  std::vector<Box> boxesAt(TimeNs t_ns) const;

  /// Distance from a world point to the nearest surface (static or moving) at time t.
  double surfaceDistance(const Eigen::Vector3d& p_w, TimeNs t_ns) const;
  /// Distance to the nearest static surface.
  double staticSurfaceDistance(const Eigen::Vector3d& p_w) const;
  /// The instance id of the moving object whose surface (or inside) is within `tolerance`
  /// of p_w at time t; 0 when none.
  int movingObjectAt(const Eigen::Vector3d& p_w, TimeNs t_ns, double tolerance = 1e-4) const;
  /// The texture of a box face: its material, the box's seed and the face's size (the face's
/// own axes in order: for face axis x, s runs along y and t along z; axis y: x, z; axis z: x, y).
FaceTexture makeFaceTexture(const Box& box, int face);

/// Nearest hit of the ray origin + s * dir, s > 1e-9, against every box (no acceleration;
  /// the reference the renderer is tested against).
  RayHit castRay(const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_w, TimeNs t_ns) const;

  /// The texture of face `face` of static box `box` (built once with the scene).
  const FaceTexture& staticTexture(size_t box, int face) const { return *static_textures_[box][face]; }

  /// A small text description (scene.txt): kind, seed, camera, boxes, persons and their paths.
  std::string describe() const;

 private:
  friend Scene makeScene(SceneKind kind, const SceneOptions& options);
  SceneKind kind_ = SceneKind::kStatic;
  SceneOptions options_;
  PinholeCamera camera_;
  std::vector<Box> static_boxes_;
  std::vector<std::array<std::shared_ptr<const FaceTexture>, 6>> static_textures_;
  std::vector<MovingObjectInfo> moving_info_;
  std::vector<WalkPath> walks_;  // one per moving object, same order
  std::optional<FastPath> fast_path_;  // the fast kind's path
  ExposureGain gain_;                  // constant 1 unless the fast kind with gain on
};

/// The texture of a box face: its material, the box's seed and the face's size (the face's
/// own axes in order: for face axis x, s runs along y and t along z; axis y: x, z; axis z: x, y).
FaceTexture makeFaceTexture(const Box& box, int face);

/// Nearest hit of the ray origin + s * dir (s > 1e-9) against every box of `boxes`
/// (RayHit::box indexes it); what Scene::castRay does with boxesAt(t).
RayHit castRay(const std::vector<Box>& boxes, const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_w);

/// Where SceneOptions::twin_shelf puts the copies: world -> world, the north shelf's place
/// onto the south wall (turned 180 degrees about z). A camera pose T_w_c before the shelf
/// becomes twinShelfTransform() * T_w_c before the copies, at the same relative pose.
SE3 twinShelfTransform();

/// Builds a scene; throws ConfigError for bad options (frames < 1, size out of range...).
Scene makeScene(SceneKind kind, const SceneOptions& options = {});

/// The camera of a scene of the given image size: fx = fy = 525 * width / 640, centre at
/// ((w-1)/2, (h-1)/2), no distortion, depth scale 5000, name "synthetic".
PinholeCamera syntheticCamera(int width, int height);

}  // namespace plslam::synth
