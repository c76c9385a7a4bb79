// The command lines of the brume sub-commands, parsed by CLI11. A command declares its
// options on a CLI::App set up by configureCommand() (the checked values through callbacks that
// call value_parsers.h) and runs parseCommand(); main() reports the UsageErrors.
#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "brume/cli/usage_error.h"

namespace brume::cli {

// Sets `app` up as a brume command: "-h, --help"; "--flag value", "--flag=value", "-o value"
// and "--" (end of options); a later value of an option replacing an earlier one; flags
// refusing a value; help in brume's layout, starting "usage: <app name> <synopsis>".
void configureCommand(CLI::App& app, const std::string& synopsis);

// The one positional argument, SCENE; a second one is a UsageError (from parseCommand()).
void addSceneArgument(CLI::App& app, std::string& scene);

// An option with a value: `take` gets the text (the last one given) once parsing is done and
// checks it (UsageError). `valueName` is the value's name in the help ("N", "WxH").
CLI::Option* addOption(CLI::App& app, const std::string& names, const std::string& valueName,
                       const std::string& description, std::function<void(const std::string&)> take);

// Parses `args` (those after the command's name). Returns false if help was asked for, after
// printing it to stdout. Whatever CLI11 rejects (an unknown option, a missing value, ...) is a
// UsageError with a one-line message; the UsageErrors of option callbacks pass unchanged.
bool parseCommand(CLI::App& app, const std::vector<std::string>& args);

}  // namespace brume::cli
