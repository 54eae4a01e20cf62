// Writing outputs so that a crash or Ctrl-C never leaves a half-written file in place.
#pragma once

#include <string>

namespace plslam {

/// Writes `content` to "<path>.tmp.<pid>", flushes it to disk, then renames it over
/// `path`. Throws IoError naming `path` on failure (the old file, if any, is left intact).
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace plslam
