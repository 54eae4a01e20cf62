// A progress line on stderr for long runs. On a terminal it is rewritten in place ("\r");
// where stderr is a file or a pipe (a log, CI, a ROS launch) it is a plain line at most
// every `log_period_s` seconds, and the last state is always printed once, so logs stay
// readable.
//
// Thread safety: one thread per ProgressLine.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace plslam::cli {

class ProgressLine {
 public:
  /// `prefix` is printed in brackets before each line ("run" -> "[run] ...").
  explicit ProgressLine(std::string prefix, double log_period_s = 5.0);
  ~ProgressLine();  ///< done()
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  /// The current state (printf-style).
  template <typename... A>
  void update(const char* format, A... args) {
    char buf[512];
    std::snprintf(buf, sizeof(buf), format, args...);
    show(buf);
  }
  /// Ends the line: a newline on a terminal; in a log, the last state if it was not printed.
  void done();

  /// True when stderr is a terminal.
  static bool terminal();

 private:
  void show(const std::string& text);

  std::string prefix_;
  double period_s_;
  bool tty_;
  bool open_ = false;     // a state was shown and the line is not ended
  bool pending_ = false;  // log mode: the last state is not printed yet
  std::string last_;
  std::chrono::steady_clock::time_point last_print_{};
};

}  // namespace plslam::cli
