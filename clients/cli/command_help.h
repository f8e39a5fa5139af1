#pragma once
// What each gaitforge command is for, the flags it reads and an example: the text of
// `gaitforge --help` (the command list) and of `gaitforge COMMAND --help`.
#include <string>
#include <vector>

namespace gaitforge::cli {

struct CommandHelp {
  std::string name;     // "hof"
  std::string args;     // "ID [--generation G]"
  std::string summary;  // one line, for the command list
  std::string details;  // what it does, for the command's own help
  std::vector<std::string> flags;  // the flags it reads (names without "--")
  std::string example;
};

// Every command, in the order `gaitforge --help` lists them.
const std::vector<CommandHelp>& Commands();
// The command named `name`, or nullptr.
const CommandHelp* FindCommand(const std::string& name);
// "commands:\n  local SPEC   run a study ...\n ..." plus the closing notes.
std::string CommandList();

}  // namespace gaitforge::cli
