#include "calibration/base_transform.h"

#include <Eigen/SVD>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/yaml.h"

namespace plslam::calib {

Eigen::Matrix3d rotationFromRpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d rpyFromRotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double roll, yaw;
  if (std::abs(R(2, 0)) < 1 - 1e-9) {
    roll = std::atan2(R(2, 1), R(2, 2));
    yaw = std::atan2(R(1, 0), R(0, 0));
  } else {  // gimbal lock: put everything into yaw
    roll = 0;
    yaw = std::atan2(-R(0, 1), R(1, 1));
  }
  return {roll, pitch, yaw};
}

SE3 parsePoseXyzRpyDeg(const std::string& text, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t used = 0;
      const double d = std::stod(item, &used);
      while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
      if (used != item.size() || !std::isfinite(d)) throw std::invalid_argument(item);
      v.push_back(d);
    } catch (const std::exception&) {
      throw ConfigError(str(what, ": '", item, "' is not a number (expected x,y,z,roll,pitch,yaw in metres and degrees)"));
    }
  }
  if (v.size() != 6)
    throw ConfigError(str(what, ": expected 6 comma-separated values x,y,z,roll,pitch,yaw (metres, degrees), got ",
                          v.size(), " in '", text, "'"));
  const double d = M_PI / 180.0;
  return SE3(rotationFromRpy(v[3] * d, v[4] * d, v[5] * d), Eigen::Vector3d(v[0], v[1], v[2]));
}

SE3 averagePoses(const std::vector<SE3>& poses) {
  if (poses.empty()) return SE3();
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (const SE3& p : poses) {
    sum += p.rotation();
    t += p.translation();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  return SE3(Eigen::Matrix3d(svd.matrixU() * D * svd.matrixV().transpose()), Eigen::Vector3d(t / poses.size()));
}

CameraToBase cameraToBase(const std::vector<SE3>& T_c_target, const SE3& T_b_target) {
  if (T_c_target.empty()) throw DataError("camera-to-base: no view with the target");
  CameraToBase out;
  for (const SE3& T : T_c_target) out.per_view.push_back(T_b_target * T.inverse());
  out.T_b_c = averagePoses(out.per_view);
  out.views = static_cast<int>(out.per_view.size());
  double st = 0, sr = 0;
  for (const SE3& p : out.per_view) {
    st += (p.translation() - out.T_b_c.translation()).squaredNorm();
    const double ang = (out.T_b_c.inverse() * p).angle() * 180.0 / M_PI;
    sr += ang * ang;
  }
  out.spread_t_m = std::sqrt(st / out.views);
  out.spread_r_deg = std::sqrt(sr / out.views);
  return out;
}

void saveCameraToBase(const std::string& path, const CameraToBase& c, const std::string& comment) {
  std::ostringstream os;
  os.precision(10);
  if (!comment.empty()) {
    std::istringstream lines(comment);
    std::string line;
    while (std::getline(lines, line)) os << "# " << line << "\n";
  }
  os << "# plslam camera-to-base transform T_b_c: p_base = T_b_c * p_camera (see src/calibration/base_transform.h).\n"
     << "# base: robot base frame (x forward, y left, z up); camera: colour optical frame (x right, y down, z forward).\n";
  const SE3& T = c.T_b_c;
  const Eigen::Quaterniond q = T.quaternion();
  const Eigen::Vector3d rpy = rpyFromRotation(T.rotation()) * 180.0 / M_PI;
  const Eigen::AngleAxisd aa(T.rotation());
  const Eigen::Vector3d tu = aa.angle() * aa.axis();
  const Eigen::Vector3d& t = T.translation();
  os << "format: plslam_camera_to_base 1\nparent_frame: base\nchild_frame: camera\n"
     << "translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n"
     << "rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n"
     << "rpy_deg: [" << rpy.x() << ", " << rpy.y() << ", " << rpy.z() << "]\n"
     << "visp_pose_vector: [" << t.x() << ", " << t.y() << ", " << t.z() << ", " << tu.x() << ", " << tu.y() << ", "
     << tu.z() << "]\n"
     << "views: " << c.views << "\nspread_translation_m: " << c.spread_t_m << "\nspread_rotation_deg: " << c.spread_r_deg
     << "\n";
  writeFileAtomically(path, os.str());
}

SE3 loadCameraToBase(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open camera-to-base file");
  std::ostringstream content;
  content << in.rdbuf();
  const YAML::Node doc = parseYaml<IoError>(content.str(), path);
  const YAML::Node format = doc.IsMap() ? doc["format"] : YAML::Node();
  if (!format || !format.IsScalar() || format.Scalar().find("plslam_camera_to_base") == std::string::npos)
    throw IoError(path + ": not a camera-to-base file (no 'format: plslam_camera_to_base 1' line)");
  const std::vector<double> t = yamlNumbersAt<IoError>(doc, "translation", 3, path);
  const std::vector<double> q = yamlNumbersAt<IoError>(doc, "rotation", 4, path);
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3)
    throw IoError(str(yamlAt(path, doc["rotation"].Mark()), ": rotation quaternion has norm ", quat.norm(), ", expected 1"));
  return SE3(quat, Eigen::Vector3d(t[0], t[1], t[2]));
}

}  // namespace plslam::calib
