#include "commands.h"

namespace plslam::cli {

std::vector<Command> allCommands() {
  return {};
}

}  // namespace plslam::cli
