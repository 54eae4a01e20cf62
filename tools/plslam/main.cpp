// plslam: one program, git-style subcommands. Each subcommand lives in its own cmd_*.cpp.
#include <cstring>
#include <exception>
#include <iostream>
#include <vector>

#include "args.h"
#include "commands.h"
#include "core/allocator.h"
#include "core/error.h"

namespace {

const std::vector<plslam::cli::Command>& commands() {
  static const std::vector<plslam::cli::Command> list = plslam::cli::allCommands();
  return list;
}

void usage(std::ostream& os) {
  os << "usage: plslam <command> [options]   (plslam <command> --help for its options)\n\n"
     << "Point-line RGB-D SLAM for dynamic scenes.\n\ncommands:\n";
  for (const auto& c : commands()) {
    std::string name = "  " + c.name;
    name.resize(12, ' ');
    os << name << c.summary << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  plslam::keepFreedMemoryForReuse();
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    usage(argc < 2 ? std::cerr : std::cout);
    return argc < 2 ? 2 : 0;
  }
  for (const auto& c : commands()) {
    if (c.name != argv[1]) continue;
    try {
      return c.run(argc - 2, argv + 2);
    } catch (const plslam::ConfigError& e) {
      std::cerr << "error: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "plslam: unknown command '" << argv[1] << "'\n\n";
  usage(std::cerr);
  return 2;
}
