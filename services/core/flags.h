#pragma once
// A small command-line parser shared by every binary: --name value or --name=value,
// booleans as --name, positional arguments, and a generated --help.
#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"

namespace gaitforge::core {

class Flags {
 public:
  // usage: "gaitforge-worker [flags]"; summary: one paragraph shown by --help. Each name
  // may be added once.
  Flags(std::string usage, std::string summary);

  void Add(const std::string& name, std::string* value, const std::string& help);
  void Add(const std::string& name, int* value, const std::string& help);
  void Add(const std::string& name, int64_t* value, const std::string& help);
  void Add(const std::string& name, double* value, const std::string& help);
  void AddBool(const std::string& name, bool* value, const std::string& help);

  // Parses argv[first..]. Returns InvalidArgument naming the flag on error. Sets
  // help_requested() for -h/--help. Non-flag arguments land in positional().
  absl::Status Parse(int argc, char** argv, int first = 1);
  bool help_requested() const { return help_; }
  const std::vector<std::string>& positional() const { return positional_; }
  std::string Help() const;
  // Help for a part of the program (a subcommand): its own usage and summary, and only the
  // flags named in `only`, in registration order.
  std::string Help(const std::string& usage, const std::string& summary,
                   const std::vector<std::string>& only) const;

 private:
  struct Flag {
    std::string name;
    std::string help;
    std::string default_text;
    bool is_bool = false;
    std::function<absl::Status(const std::string&)> set;
  };
  // Adds a flag; a name registered twice aborts.
  void Register(Flag flag);

  std::string usage_, summary_;
  std::vector<Flag> flags_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

}  // namespace gaitforge::core
