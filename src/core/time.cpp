#include "core/time.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>

namespace plslam {

bool parseSecondsStamp(const std::string& text, TimeNs* t_ns) {
  size_t i = 0;
  int64_t whole = 0;
  int64_t frac_ns = 0;
  bool digits = false;
  for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
    whole = whole * 10 + (text[i] - '0');
    // Beyond ~285 years: whole * kNsPerSecond would overflow int64 (checked after each
    // digit, so `whole` itself never exceeds 9e10).
    if (whole > 9'000'000'000LL) return false;
    digits = true;
  }
  if (i < text.size() && text[i] == '.') {
    ++i;
    int64_t scale = 100'000'000LL;
    for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
      frac_ns += (text[i] - '0') * scale;
      scale /= 10;
      digits = true;
    }
  }
  if (!digits || i != text.size()) return false;
  *t_ns = whole * kNsPerSecond + frac_ns;
  return true;
}

std::string formatSecondsStamp(TimeNs t_ns) {
  const bool negative = t_ns < 0;
  const uint64_t a = static_cast<uint64_t>(negative ? -t_ns : t_ns);
  const uint64_t us = (a + 500) / 1000;  // round to microseconds
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%s%llu.%06llu", negative ? "-" : "",
                static_cast<unsigned long long>(us / 1000000ULL), static_cast<unsigned long long>(us % 1000000ULL));
  return buf;
}

}  // namespace plslam
