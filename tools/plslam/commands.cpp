#include "commands.h"

namespace plslam::cli {

std::vector<Command> allCommands() {
  return {
      makeRunCommand(),
      makeEvalCommand(),
      makeSynthCommand(),
      makeBenchCommand(),
  };
}

}  // namespace plslam::cli
