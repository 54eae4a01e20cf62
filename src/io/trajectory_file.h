// TUM trajectory files: "timestamp tx ty tz qx qy qz qw" per line, '#' comments,
// T_w_c (camera pose in the world), metres, seconds.
#pragma once

#include <string>

#include "core/trajectory.h"

namespace plslam {

struct TrajectoryReadReport {
  int lines_read = 0;
  int skipped_malformed = 0;   ///< wrong field count or non-numeric field
  int skipped_nonfinite = 0;   ///< NaN/inf in a field
  int skipped_zero_quat = 0;   ///< quaternion of (near) zero norm
  int duplicates_dropped = 0;  ///< later lines with an already seen stamp (the TUM tools keep the last; so do we)
  bool was_unsorted = false;   ///< stamps were not increasing (the result is sorted)
};

/// Reads a TUM trajectory. Like the TUM tools' read_file_list, commas and tabs count as
/// spaces, a duplicated stamp keeps the last pose, and the result is sorted by time.
/// Lines that cannot be a pose are skipped and counted in `report` (and logged); an
/// unreadable file, or one with no valid pose, throws IoError naming the file.
Trajectory readTumTrajectory(const std::string& path, TrajectoryReadReport* report = nullptr);
/// The same on file content in memory; `source` names it in messages.
Trajectory parseTumTrajectory(const std::string& content, const std::string& source,
                              TrajectoryReadReport* report = nullptr);

/// Writes a TUM trajectory (6 decimals for stamps, 9 significant digits for values),
/// atomically: a temporary file is renamed over `path`, so a crash never leaves half a file.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& header_comment = "");

}  // namespace plslam
