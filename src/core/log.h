// One logger per module, one process-wide sink. The library never writes to std::cout;
// messages go to the sink (stderr by default) with the module name in front.
//
// Thread safety: all functions may be called from any thread.
#pragma once

#include <functional>
#include <sstream>
#include <string>

namespace plslam {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarn = 2, kError = 3, kOff = 4 };

using LogSink = std::function<void(LogLevel, const std::string& module, const std::string& message)>;

/// Messages below `level` are dropped. Default kInfo.
void setLogLevel(LogLevel level);
LogLevel logLevel();
/// Replaces the sink (nullptr restores the stderr sink). Tests use this to capture messages.
void setLogSink(LogSink sink);
/// Parses "debug", "info", "warn", "error", "off"; throws ConfigError otherwise.
LogLevel parseLogLevel(const std::string& text);

class Logger {
 public:
  explicit Logger(std::string module) : module_(std::move(module)) {}
  void log(LogLevel level, const std::string& message) const;
  void debug(const std::string& m) const { log(LogLevel::kDebug, m); }
  void info(const std::string& m) const { log(LogLevel::kInfo, m); }
  void warn(const std::string& m) const { log(LogLevel::kWarn, m); }
  void error(const std::string& m) const { log(LogLevel::kError, m); }
  bool enabled(LogLevel level) const { return level >= logLevel(); }

 private:
  std::string module_;
};

/// Concatenates its arguments with operator<<: str("frame ", i, " skipped").
template <typename... Args>
std::string str(const Args&... args) {
  std::ostringstream os;
  (os << ... << args);
  return os.str();
}

}  // namespace plslam
