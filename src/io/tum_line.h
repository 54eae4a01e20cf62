// One line of a TUM text file (rgb.txt, depth.txt, groundtruth.txt, trajectories) as the
// TUM tools' read_file_list sees it: commas and tabs are spaces, a trailing CR is dropped,
// blank lines and lines starting with '#' carry nothing.
#pragma once

#include <string>
#include <vector>

namespace plslam {

/// The whitespace-separated fields of `line`; false (and no fields) for a blank or
/// comment line.
bool splitTumLine(const std::string& line, std::vector<std::string>* fields);

}  // namespace plslam
