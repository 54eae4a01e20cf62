#include "io/associate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <tuple>

namespace plslam {

double stampSeconds(TimeNs t_ns) {
  // strtod rounds the exact decimal correctly, as Python's float() does.
  const bool negative = t_ns < 0;
  const unsigned long long a = negative ? 0ULL - static_cast<unsigned long long>(t_ns) : static_cast<unsigned long long>(t_ns);
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%s%llu.%09llu", negative ? "-" : "", a / 1'000'000'000ULL, a % 1'000'000'000ULL);
  return std::strtod(buf, nullptr);
}

std::vector<StampMatch> associateStamps(const std::vector<TimeNs>& first, const std::vector<TimeNs>& second,
                                        double max_difference_s, double offset_s) {
  std::vector<double> a(first.size()), b(second.size());
  std::transform(first.begin(), first.end(), a.begin(), stampSeconds);
  std::transform(second.begin(), second.end(), b.begin(), [&](TimeNs t) { return stampSeconds(t) + offset_s; });

  // Second list sorted by shifted stamp, so each first stamp only looks at its window.
  std::vector<size_t> order(b.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return b[x] < b[y]; });
  std::vector<double> b_sorted(b.size());
  for (size_t k = 0; k < order.size(); ++k) b_sorted[k] = b[order[k]];

  struct Candidate {
    double diff;
    double ta, tb;  // the Python tuple (diff, a, b) sorts by these, in this order
    size_t i, j;
  };
  std::vector<Candidate> candidates;
  for (size_t i = 0; i < a.size(); ++i) {
    // Generous window in the sorted list, then the exact test associate.py uses.
    auto lo = std::lower_bound(b_sorted.begin(), b_sorted.end(), a[i] - max_difference_s - 1e-6);
    for (auto it = lo; it != b_sorted.end() && *it <= a[i] + max_difference_s + 1e-6; ++it) {
      const size_t j = order[static_cast<size_t>(it - b_sorted.begin())];
      const double diff = std::abs(a[i] - b[j]);
      if (diff < max_difference_s) candidates.push_back({diff, a[i], stampSeconds(second[j]), i, j});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.diff, x.ta, x.tb) < std::tie(y.diff, y.ta, y.tb);
  });

  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<StampMatch> matches;
  for (const Candidate& c : candidates) {
    if (used_a[c.i] || used_b[c.j]) continue;
    used_a[c.i] = used_b[c.j] = 1;
    matches.push_back({c.i, c.j});
  }
  std::sort(matches.begin(), matches.end(), [&](const StampMatch& x, const StampMatch& y) {
    return first[x.first] != first[y.first] ? first[x.first] < first[y.first] : second[x.second] < second[y.second];
  });
  return matches;
}

size_t findClosestIndex(const std::vector<double>& L, double t) {
  size_t begin = 0, end = L.size(), best = 0;
  double difference = std::abs(L[0] - t);
  while (begin < end) {
    const size_t middle = (begin + end) / 2;
    if (std::abs(L[middle] - t) < difference) {
      difference = std::abs(L[middle] - t);
      best = middle;
    }
    if (t == L[middle]) return middle;
    if (L[middle] > t) {
      end = middle;
    } else {
      begin = middle + 1;
    }
  }
  return best;
}

}  // namespace plslam
