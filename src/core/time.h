// Time is int64_t nanoseconds everywhere inside; seconds with 6 decimals only in TUM files.
#pragma once

#include <cstdint>
#include <string>

namespace plslam {

using TimeNs = int64_t;

constexpr TimeNs kNsPerSecond = 1'000'000'000LL;

inline double nsToSeconds(TimeNs t) { return static_cast<double>(t) * 1e-9; }
inline TimeNs secondsToNs(double s) { return static_cast<TimeNs>(s * 1e9 + (s >= 0 ? 0.5 : -0.5)); }

/// Parses a decimal seconds stamp such as "1305031102.175304" exactly (no double rounding).
/// Returns false when `text` is not a plain non-negative decimal number.
bool parseSecondsStamp(const std::string& text, TimeNs* t_ns);
/// Formats as seconds with 6 decimals, the TUM convention.
std::string formatSecondsStamp(TimeNs t_ns);

}  // namespace plslam
