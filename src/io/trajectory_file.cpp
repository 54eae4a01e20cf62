#include "io/trajectory_file.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "io/tum_line.h"
#include "core/atomic_file.h"

namespace plslam {

namespace {
const Logger kLog("io");

bool toDouble(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0';
}
}  // namespace

Trajectory readTumTrajectory(const std::string& path, TrajectoryReadReport* report) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open trajectory file");
  std::ostringstream content;
  content << file.rdbuf();
  if (file.bad()) throw IoError(path + ": read error");
  return parseTumTrajectory(content.str(), path, report);
}

Trajectory parseTumTrajectory(const std::string& content, const std::string& path, TrajectoryReadReport* report) {
  std::istringstream in(content);
  TrajectoryReadReport r;
  std::map<TimeNs, SE3> poses;
  std::string line;
  TimeNs last = 0;
  bool first = true;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::vector<std::string> f;
    if (!splitTumLine(line, &f)) continue;
    ++r.lines_read;
    double v[8];
    bool ok = f.size() == 8;
    for (int i = 0; ok && i < 8; ++i) ok = toDouble(f[i], &v[i]);
    if (!ok) {
      ++r.skipped_malformed;
      kLog.debug(str(path, ":", lineno, ": not a pose line, skipped"));
      continue;
    }
    if (!std::all_of(v, v + 8, [](double x) { return std::isfinite(x); })) {
      ++r.skipped_nonfinite;
      continue;
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (q.norm() < 1e-6) {
      ++r.skipped_zero_quat;
      continue;
    }
    TimeNs t = 0;
    if (!parseSecondsStamp(f[0], &t)) {
      // Exponents etc.; a stamp beyond int64 nanoseconds (~292 years) is not a stamp.
      if (std::abs(v[0]) > 9.0e9) {
        ++r.skipped_malformed;
        kLog.debug(str(path, ":", lineno, ": stamp out of range, skipped"));
        continue;
      }
      t = secondsToNs(v[0]);
    }
    if (!first && t <= last) r.was_unsorted |= t < last;
    first = false;
    last = t;
    if (poses.count(t)) ++r.duplicates_dropped;
    poses[t] = SE3(q, Eigen::Vector3d(v[1], v[2], v[3]));
  }
  const int skipped = r.skipped_malformed + r.skipped_nonfinite + r.skipped_zero_quat;
  if (skipped > 0)
    kLog.warn(str(path, ": skipped ", skipped, " of ", r.lines_read, " lines (", r.skipped_malformed, " malformed, ",
                  r.skipped_nonfinite, " not finite, ", r.skipped_zero_quat, " zero quaternion)"));
  if (r.duplicates_dropped > 0) kLog.warn(str(path, ": ", r.duplicates_dropped, " duplicated stamps (the last pose kept)"));
  if (r.was_unsorted) kLog.info(path + ": stamps were not in order; sorted");
  if (poses.empty()) throw IoError(path + ": no valid pose line (expected 'timestamp tx ty tz qx qy qz qw')");
  if (report) *report = r;
  Trajectory out;
  out.reserve(poses.size());
  for (const auto& [t, T] : poses) out.push_back({t, T});
  return out;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& header_comment) {
  std::ostringstream os;
  if (!header_comment.empty()) os << "# " << header_comment << "\n";
  os << "# timestamp tx ty tz qx qy qz qw\n";
  char buf[256];
  for (const auto& p : trajectory) {
    const Eigen::Vector3d& t = p.T_w_c.translation();
    const Eigen::Quaterniond& q = p.T_w_c.quaternion();
    std::snprintf(buf, sizeof(buf), "%s %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", formatSecondsStamp(p.t_ns).c_str(), t.x(),
                  t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
    os << buf;
  }
  writeFileAtomically(path, os.str());
}

}  // namespace plslam
