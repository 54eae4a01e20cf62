// Timestamp association exactly as the TUM RGB-D tools' associate.py does it: every pair
// of stamps closer than max_difference is a candidate; candidates are taken greedily,
// smallest difference first, each stamp used at most once; the result is sorted by the
// first list's stamps. Differences are computed on the stamps as the Python tools read
// them (the nearest double to the decimal seconds), so ties break the same way.
#pragma once

#include <cstddef>
#include <vector>

#include "core/time.h"

namespace plslam {

/// One associated pair: indices into the first and second stamp lists.
struct StampMatch {
  size_t first = 0;
  size_t second = 0;
};

/// The stamp as Python's float("<seconds>") gives it: the double nearest to t_ns / 1e9
/// (t_ns / 1e9 computed in double is not always that).
double stampSeconds(TimeNs t_ns);

/// associate.py's associate(first, second, offset, max_difference): pairs (i, j) with
/// |first[i] - (second[j] + offset_s)| < max_difference_s, greedily by smallest
/// difference (ties: smaller first stamp, then smaller second stamp), each index used
/// once, sorted by first[i]. Stamps within one list are expected to be distinct (as the
/// keys of the Python dictionaries are); the lists need not be sorted.
std::vector<StampMatch> associateStamps(const std::vector<TimeNs>& first, const std::vector<TimeNs>& second,
                                        double max_difference_s = 0.02, double offset_s = 0.0);

/// Index of the stamp in `sorted_seconds` closest to t, found with the TUM tools'
/// find_closest_index binary search (on a tie the element visited first wins).
/// `sorted_seconds` must be sorted ascending and non-empty.
size_t findClosestIndex(const std::vector<double>& sorted_seconds, double t);

}  // namespace plslam
