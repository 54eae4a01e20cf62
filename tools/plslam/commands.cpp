#include "commands.h"

namespace plslam::cli {

std::vector<Command> allCommands() {
  return {
      makeRunCommand(),
      makeEvalCommand(),
      makeSynthCommand(),
      makeBenchCommand(),
      makeLiveCommand(),
      makeRecordCommand(),
      makeServoCommand(),
      makeVocabCommand(),
      makeCalibCommand(),
      makeExportCommand(),
  };
}

}  // namespace plslam::cli
