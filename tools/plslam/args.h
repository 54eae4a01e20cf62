// The shared option handling of every `plslam` subcommand: declared options with a
// help line and default, "--name value" or "--name=value", flags, positional-free.
// Unknown options and bad values are refused with a message naming them.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace plslam::cli {

class Args {
 public:
  Args(std::string command, std::string summary) : command_(std::move(command)), summary_(std::move(summary)) {}

  /// Declares an option taking a value. An empty default with required=true means it must be given.
  Args& option(const std::string& name, const std::string& help, const std::string& fallback = "", bool required = false);
  /// Declares a flag (no value).
  Args& flag(const std::string& name, const std::string& help);
  /// Adds free text under the option list (examples, notes).
  Args& epilog(const std::string& text) {
    epilog_ = text;
    return *this;
  }

  /// Parses argv (after the subcommand). Returns false when --help was asked for (help is
  /// printed to stdout). Throws ConfigError on unknown options or missing values.
  bool parse(int argc, char** argv);

  bool has(const std::string& name) const;  ///< given on the command line (or a flag set)
  std::string str(const std::string& name) const;
  int integer(const std::string& name, int min_value, int max_value) const;
  double number(const std::string& name) const;
  std::string help() const;

 private:
  struct Spec {
    std::string help, fallback;
    bool is_flag = false, required = false;
  };
  std::string command_, summary_, epilog_;
  std::vector<std::string> order_;
  std::map<std::string, Spec> specs_;
  std::map<std::string, std::string> values_;
};

/// A subcommand: its name, a one-line summary for `plslam --help`, and its entry point.
struct Command {
  std::string name;
  std::string summary;
  std::function<int(int, char**)> run;
};

}  // namespace plslam::cli
