// Calibration targets: a chessboard and an AprilTag grid ("Aprilgrid"-like board of
// tag36h11 tags), described by a short spec string that the CLI takes as it is:
//
//   chessboard:COLSxROWS:SQUARE             inner corners, square edge in metres
//   aprilgrid:COLSxROWS:TAG:SPACING[:ID0]   tags, tag edge (outer edge of the black border),
//                                           gap between tags, id of the first tag (default 0)
//   tag:ID:SIZE                             one tag36h11 tag (= aprilgrid:1x1:SIZE:0:ID)
//
// Board frame (the same as OpenCV's object points): origin at the first inner corner
// (chessboard) or at the top-left corner of the first tag's black border (aprilgrid),
// x along a row to the right as printed, y down the columns, z into the board (away from
// a camera that sees its printed face). Tag ids run row by row: id = ID0 + row*COLS + col.
// The *target frame* used by the camera-to-base calibration has the same axes with its
// origin at the centre of the pattern (the tag centre for a single tag).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/se3.h"

namespace plslam::calib {

enum class TargetKind { kChessboard, kAprilGrid };

struct Target {
  TargetKind kind = TargetKind::kChessboard;
  int cols = 9;            ///< chessboard: inner corners per row; aprilgrid: tags per row
  int rows = 6;            ///< chessboard: inner corners per column; aprilgrid: tags per column
  double size = 0.025;     ///< chessboard: square edge; aprilgrid: tag edge (black border), metres
  double spacing = 0.0;    ///< aprilgrid: gap between neighbouring tags, metres
  int first_id = 0;        ///< aprilgrid: id of the top-left tag (tag36h11 has ids 0..586)

  /// Parses a spec (see above). Throws ConfigError naming the spec and the problem.
  static Target parse(const std::string& spec);
  /// The spec string of this target (parse(t.spec()) == t).
  std::string spec() const;
  /// Throws ConfigError when a field is out of range.
  void validate() const;

  /// Number of points: chessboard inner corners, or 4 per tag.
  int pointCount() const;
  /// Board-frame coordinates of every point (z = 0), in point-id order: chessboard row by
  /// row; aprilgrid tag by tag in id order, each tag's corners in the apriltag library's
  /// order (bottom-left, bottom-right, top-right, top-left as printed).
  std::vector<cv::Point3f> points() const;
  /// Point id of corner `corner` (0..3, library order) of tag `tag_id`; -1 when the tag
  /// is not on this board.
  int tagPointId(int tag_id, int corner) const;
  /// The printed area in board coordinates (pattern plus the white margin a detector needs).
  cv::Rect2d printedArea() const;
  /// The pattern's extent (outer corners of the corner grid / of all tags).
  cv::Rect2d patternArea() const;
  /// T_board_target: the target frame (pattern centre) in the board frame.
  SE3 boardFromTarget() const;
  /// Edge of one tag bit cell (aprilgrid), metres.
  double tagCell() const { return size / 8.0; }

  bool operator==(const Target& o) const {
    return kind == o.kind && cols == o.cols && rows == o.rows && size == o.size && spacing == o.spacing &&
           first_id == o.first_id;
  }
};

}  // namespace plslam::calib
