#include "servo_sim/rendered_sensors.h"

#include <algorithm>

#include "camera/visp_conversion.h"
#include "core/time.h"

namespace plslam {

namespace {

// The frames' stamps: an arbitrary epoch plus the simulated time.
TimeNs stamp(int step, double dt) { return 1'600'000'000LL * kNsPerSecond + secondsToNs(step * dt); }

}  // namespace

SE3 defaultPlaneInRoom() { return SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-1.2, 0.3, 0)); }

SE3 planeForTagOnEastWall(double tag_x, double tag_y) {
  return SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(3.0 - tag_x, -0.8 - tag_y, 0));
}

SystemOptions servoSlamOptions() {
  SystemOptions o;
  o.sequential = true;
  o.dense.enabled = false;
  o.use_loop = false;
  return o;
}

SlamPoses::SlamPoses(const TagRoom& room, const SE3& T_room_w, double dt, const SystemOptions& options)
    : room_(room), T_room_w_(T_room_w), dt_(dt), slam_(std::make_unique<System>(room.camera(), options)) {
  slam_->start();
}

SlamPoses::~SlamPoses() {
  try {
    slam_->finish();
  } catch (...) {  // a destructor must not throw; the loop has its poses already
  }
}

std::optional<vpHomogeneousMatrix> SlamPoses::measure(int step, const vpHomogeneousMatrix& wMc_true) {
  const SE3 T_w_c_true = fromVisp(wMc_true);
  const synth::RenderedFrame view = room_.render(T_room_w_ * T_w_c_true, stamp(step, dt_), static_cast<uint64_t>(step));
  RgbdFrame frame = view.toRgbdFrame();
  frame.index = step;
  const TrackingResult r = slam_->feed(frame);
  ++frames_;
  if (!isTracked(r.status)) {
    ++lost_;
    return std::nullopt;
  }
  if (!T_w_slam_) T_w_slam_ = T_w_c_true * r.T_w_c.inverse();
  const SE3 T_w_c = *T_w_slam_ * r.T_w_c;
  max_position_error_ = std::max(max_position_error_, (T_w_c.translation() - T_w_c_true.translation()).norm());
  return toVisp(T_w_c);
}

DetectedTag::DetectedTag(const TagRoom& room, const SE3& T_room_p)
    : room_(room),
      T_room_p_(T_room_p),
      detector_(room.camera(), room.options().tag_id, room.options().tag_size) {}

std::optional<vpHomogeneousMatrix> DetectedTag::observe(int step, const vpHomogeneousMatrix& pMc_true) {
  // The room is static: the stamp only names the view; the step picks its sensor noise.
  const synth::RenderedFrame view =
      room_.render(T_room_p_ * fromVisp(pMc_true), stamp(step, 1.0 / 30), static_cast<uint64_t>(step));
  const std::optional<SE3> T_c_tag = detector_.detect(view.bgr);
  if (!T_c_tag) {
    ++misses_;
    return std::nullopt;
  }
  ++detections_;
  return toVisp(*T_c_tag);
}

}  // namespace plslam
