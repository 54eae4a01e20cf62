// The table of subcommands. Each cmd_*.cpp defines one make*Command().
#pragma once

#include <vector>

#include "args.h"

namespace plslam::cli {

std::vector<Command> allCommands();

Command makeEvalCommand();
Command makeSynthCommand();
Command makeRunCommand();
Command makeBenchCommand();
Command makeLiveCommand();
Command makeRecordCommand();
Command makeServoCommand();
Command makeVocabCommand();
Command makeCalibCommand();
Command makeExportCommand();
/// plslam eval loops (cmd_eval_loops.cpp): argv after "loops".
int runEvalLoops(int argc, char** argv);
/// plslam eval masks (cmd_eval_masks.cpp): argv after "masks".
int runEvalMasks(int argc, char** argv);

}  // namespace plslam::cli
