#include "calibration/target.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/log.h"

namespace plslam::calib {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

double parseNumber(const std::string& text, const std::string& spec, const char* what) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw ConfigError(str("target '", spec, "': ", what, " '", text, "' is not a number"));
}

int parseInt(const std::string& text, const std::string& spec, const char* what) {
  const double v = parseNumber(text, spec, what);
  if (v != std::floor(v) || std::abs(v) > 1e6) throw ConfigError(str("target '", spec, "': ", what, " '", text, "' is not a whole number"));
  return static_cast<int>(v);
}

void parseGrid(const std::string& text, const std::string& spec, int& cols, int& rows) {
  const auto p = split(text, 'x');
  if (p.size() != 2) throw ConfigError(str("target '", spec, "': grid '", text, "' should be COLSxROWS, e.g. 9x6"));
  cols = parseInt(p[0], spec, "column count");
  rows = parseInt(p[1], spec, "row count");
}

constexpr const char* kSpecHelp =
    "expected chessboard:COLSxROWS:SQUARE_M, aprilgrid:COLSxROWS:TAG_M:SPACING_M[:FIRST_ID] or tag:ID:SIZE_M";

}  // namespace

Target Target::parse(const std::string& spec) {
  const auto f = split(spec, ':');
  Target t;
  if (f[0] == "chessboard") {
    if (f.size() != 3) throw ConfigError(str("target '", spec, "': ", kSpecHelp));
    t.kind = TargetKind::kChessboard;
    parseGrid(f[1], spec, t.cols, t.rows);
    t.size = parseNumber(f[2], spec, "square size");
  } else if (f[0] == "aprilgrid") {
    if (f.size() != 4 && f.size() != 5) throw ConfigError(str("target '", spec, "': ", kSpecHelp));
    t.kind = TargetKind::kAprilGrid;
    parseGrid(f[1], spec, t.cols, t.rows);
    t.size = parseNumber(f[2], spec, "tag size");
    t.spacing = parseNumber(f[3], spec, "tag spacing");
    if (f.size() == 5) t.first_id = parseInt(f[4], spec, "first tag id");
  } else if (f[0] == "tag") {
    if (f.size() != 3) throw ConfigError(str("target '", spec, "': ", kSpecHelp));
    t.kind = TargetKind::kAprilGrid;
    t.cols = t.rows = 1;
    t.first_id = parseInt(f[1], spec, "tag id");
    t.size = parseNumber(f[2], spec, "tag size");
    t.spacing = 0;
  } else {
    throw ConfigError(str("target '", spec, "': unknown kind '", f[0], "'; ", kSpecHelp));
  }
  try {
    t.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(str("target '", spec, "': ", e.what()));
  }
  return t;
}

std::string Target::spec() const {
  std::ostringstream os;
  os.precision(10);
  if (kind == TargetKind::kChessboard) {
    os << "chessboard:" << cols << "x" << rows << ":" << size;
  } else if (cols == 1 && rows == 1 && spacing == 0) {
    os << "tag:" << first_id << ":" << size;
  } else {
    os << "aprilgrid:" << cols << "x" << rows << ":" << size << ":" << spacing;
    if (first_id != 0) os << ":" << first_id;
  }
  return os.str();
}

void Target::validate() const {
  if (!(size > 0) || size > 10) throw ConfigError(str("size ", size, " m must be in (0, 10]"));
  if (kind == TargetKind::kChessboard) {
    if (cols < 2 || rows < 2 || cols > 100 || rows > 100)
      throw ConfigError(str("a chessboard needs 2..100 inner corners per side, got ", cols, "x", rows));
  } else {
    if (cols < 1 || rows < 1 || cols * rows > 587) throw ConfigError(str("grid ", cols, "x", rows, " is empty or larger than 587 tags"));
    if (spacing < 0) throw ConfigError(str("tag spacing ", spacing, " m is negative"));
    if (first_id < 0 || first_id + cols * rows > 587)
      throw ConfigError(str("tag ids ", first_id, "..", first_id + cols * rows - 1, " exceed tag36h11's 0..586"));
  }
}

int Target::pointCount() const { return kind == TargetKind::kChessboard ? cols * rows : 4 * cols * rows; }

std::vector<cv::Point3f> Target::points() const {
  std::vector<cv::Point3f> out;
  out.reserve(pointCount());
  if (kind == TargetKind::kChessboard) {
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) out.emplace_back(static_cast<float>(c * size), static_cast<float>(r * size), 0.f);
    return out;
  }
  const double pitch = size + spacing;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double x0 = c * pitch, y0 = r * pitch;
      // apriltag's corner order: (-1,1) (1,1) (1,-1) (-1,-1) in tag coordinates, y down.
      out.emplace_back(static_cast<float>(x0), static_cast<float>(y0 + size), 0.f);
      out.emplace_back(static_cast<float>(x0 + size), static_cast<float>(y0 + size), 0.f);
      out.emplace_back(static_cast<float>(x0 + size), static_cast<float>(y0), 0.f);
      out.emplace_back(static_cast<float>(x0), static_cast<float>(y0), 0.f);
    }
  }
  return out;
}

int Target::tagPointId(int tag_id, int corner) const {
  if (kind != TargetKind::kAprilGrid || corner < 0 || corner > 3) return -1;
  const int k = tag_id - first_id;
  if (k < 0 || k >= cols * rows) return -1;
  return 4 * k + corner;
}

cv::Rect2d Target::patternArea() const {
  if (kind == TargetKind::kChessboard) return {-size, -size, (cols + 1) * size, (rows + 1) * size};
  return {0, 0, cols * size + (cols - 1) * spacing, rows * size + (rows - 1) * spacing};
}

cv::Rect2d Target::printedArea() const {
  const cv::Rect2d p = patternArea();
  // A chessboard detector wants a white frame about one square wide; a tag needs at least
  // one bit cell of white around its black border (two here, for blur).
  const double m = kind == TargetKind::kChessboard ? size : std::max(spacing, 2 * tagCell());
  return {p.x - m, p.y - m, p.width + 2 * m, p.height + 2 * m};
}

SE3 Target::boardFromTarget() const {
  Eigen::Vector3d c;
  if (kind == TargetKind::kChessboard) {
    c = {0.5 * (cols - 1) * size, 0.5 * (rows - 1) * size, 0.0};
  } else {
    const cv::Rect2d p = patternArea();
    c = {p.x + 0.5 * p.width, p.y + 0.5 * p.height, 0.0};
  }
  return SE3(Eigen::Quaterniond::Identity(), c);
}

}  // namespace plslam::calib
