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

}  // namespace plslam::cli
