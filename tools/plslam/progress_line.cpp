#include "progress_line.h"

#include <unistd.h>

namespace plslam::cli {

ProgressLine::ProgressLine(std::string prefix, double log_period_s)
    : prefix_(std::move(prefix)), period_s_(log_period_s), tty_(terminal()) {}

ProgressLine::~ProgressLine() { done(); }

bool ProgressLine::terminal() { return isatty(fileno(stderr)) == 1; }

void ProgressLine::show(const std::string& text) {
  last_ = text;
  if (tty_) {
    std::fprintf(stderr, "\r[%s] %s  ", prefix_.c_str(), text.c_str());
    std::fflush(stderr);
    open_ = true;
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  pending_ = true;
  if (open_ && std::chrono::duration<double>(now - last_print_).count() < period_s_) return;
  std::fprintf(stderr, "[%s] %s\n", prefix_.c_str(), text.c_str());
  open_ = true;
  pending_ = false;
  last_print_ = now;
}

void ProgressLine::done() {
  if (!open_ && !pending_) return;
  if (tty_) std::fprintf(stderr, "\n");
  else if (pending_) std::fprintf(stderr, "[%s] %s\n", prefix_.c_str(), last_.c_str());
  std::fflush(stderr);
  open_ = pending_ = false;
}

}  // namespace plslam::cli
