#include "ros_messages.h"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <cstdio>
#include <cstring>

namespace plslam::ros1 {

geometry_msgs::Pose toPose(const SE3& T) {
  geometry_msgs::Pose p;
  p.position.x = T.translation().x();
  p.position.y = T.translation().y();
  p.position.z = T.translation().z();
  p.orientation.x = T.quaternion().x();
  p.orientation.y = T.quaternion().y();
  p.orientation.z = T.quaternion().z();
  p.orientation.w = T.quaternion().w();
  return p;
}

geometry_msgs::Transform toTransform(const SE3& T) {
  const geometry_msgs::Pose p = toPose(T);
  geometry_msgs::Transform t;
  t.translation.x = p.position.x;
  t.translation.y = p.position.y;
  t.translation.z = p.position.z;
  t.rotation = p.orientation;
  return t;
}

SE3 fromPose(const geometry_msgs::Pose& pose) {
  const geometry_msgs::Quaternion& q = pose.orientation;
  return SE3(Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix(),
             Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
}

SE3 fromTransform(const geometry_msgs::Transform& t) {
  return SE3(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z),
             Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
}

sensor_msgs::PointCloud2 pointsMessage(const SparseMapSnapshot& map, const SE3& T_map_world,
                                       const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(map.points.size());
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const Eigen::Vector3d& p_w : map.points) {
    const Eigen::Vector3d p = T_map_world * p_w;
    *x = static_cast<float>(p.x());
    *y = static_cast<float>(p.y());
    *z = static_cast<float>(p.z());
    ++x, ++y, ++z;
  }
  return cloud;
}

visualization_msgs::Marker linesMessage(const SparseMapSnapshot& map, const SE3& T_map_world,
                                        const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = "plslam_lines";
  m.id = 0;
  m.type = visualization_msgs::Marker::LINE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1;
  m.scale.x = 0.01;  // line width, metres
  m.color.r = 1;
  m.color.a = 1;
  m.points.reserve(2 * map.lines.size());
  for (const auto& [P_w, Q_w] : map.lines) {
    for (const Eigen::Vector3d& e : {T_map_world * P_w, T_map_world * Q_w}) {
      geometry_msgs::Point p;
      p.x = e.x(), p.y = e.y(), p.z = e.z();
      m.points.push_back(p);
    }
  }
  return m;
}

sensor_msgs::PointCloud2 denseCloudMessage(const std::vector<FusedPoint>& cloud, const SE3& T_pub_map,
                                           const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  modifier.setPointCloud2Fields(5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                "z", 1, sensor_msgs::PointField::FLOAT32, "rgb", 1, sensor_msgs::PointField::FLOAT32,
                                "label", 1, sensor_msgs::PointField::UINT32);
  modifier.resize(cloud.size());
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), rgb(msg, "rgb");
  sensor_msgs::PointCloud2Iterator<uint32_t> label(msg, "label");
  const Eigen::Matrix3f R = T_pub_map.rotation().cast<float>();
  const Eigen::Vector3f t = T_pub_map.translation().cast<float>();
  for (const FusedPoint& p : cloud) {
    const Eigen::Vector3f q = R * p.p_w + t;
    x[0] = q.x(), x[1] = q.y(), x[2] = q.z();
    const Rgb c = semanticColour(p);
    const uint32_t packed = (uint32_t(c.r) << 16) | (uint32_t(c.g) << 8) | uint32_t(c.b);
    std::memcpy(&*rgb, &packed, 4);
    *label = static_cast<uint32_t>(p.class_id + 1);
    ++x, ++rgb, ++label;
  }
  return msg;
}

nav_msgs::OccupancyGrid gridMessage(const OccupancyGrid& grid, const SE3& T_pub_map, const std_msgs::Header& header) {
  nav_msgs::OccupancyGrid msg;
  msg.header = header;
  msg.info.map_load_time = header.stamp;
  msg.info.resolution = static_cast<float>(grid.resolution);
  msg.info.width = static_cast<uint32_t>(grid.width);
  msg.info.height = static_cast<uint32_t>(grid.height);
  const SE3 T_map_origin(Eigen::Quaterniond::Identity(), Eigen::Vector3d(grid.origin.x(), grid.origin.y(), 0));
  msg.info.origin = toPose(T_pub_map * T_map_origin);
  msg.data.assign(grid.cells.begin(), grid.cells.end());
  return msg;
}

diagnostic_msgs::DiagnosticArray statusMessage(const FrameOutcome& frame, const SessionCounts& counts,
                                               double latency_ms, const std_msgs::Header& header) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "plslam: tracking";
  s.hardware_id = header.frame_id;
  s.level = frame.tracked ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
  s.message = frame.tracked ? "tracked" : "not tracked: " + frame.reason;
  auto add = [&](const std::string& key, const std::string& value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    kv.value = value;
    s.values.push_back(kv);
  };
  char ms[32];
  std::snprintf(ms, sizeof(ms), "%.2f", frame.tracking_ms);
  add("status", toString(frame.status));
  add("tracking_ms", ms);
  std::snprintf(ms, sizeof(ms), "%.2f", latency_ms);
  add("latency_ms", ms);
  add("keyframes", std::to_string(frame.keyframes));
  add("mode", frame.localizing ? "localising" : "mapping");
  add("resets", std::to_string(frame.resets));
  add("received", std::to_string(counts.received));
  add("processed", std::to_string(counts.processed));
  add("dropped", std::to_string(counts.dropped));
  add("tracked", std::to_string(counts.tracked));
  diagnostic_msgs::DiagnosticArray a;
  a.header = header;
  a.status.push_back(s);
  return a;
}

}  // namespace plslam::ros1
