#pragma once
// Real processes on loopback: a gaitforge-coordinator, gaitforge-worker processes and
// gaitforge CLI invocations, for end-to-end tests.
#include <sys/types.h>

#include <string>
#include <vector>

namespace gaitforge::testing {

std::string Bin(const std::string& name);

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs a command line through /bin/sh and captures its output.
CommandResult RunCommand(const std::string& command_line);

class LocalCluster {
 public:
  // Starts a coordinator on db (port 0 on 127.0.0.1) logging into dir.
  LocalCluster(const std::string& dir, const std::string& db,
               const std::vector<std::string>& extra_flags = {});
  ~LocalCluster();
  void StartWorkers(int n, int threads = 1);
  void StopWorkers();
  void StopCoordinator();
  const std::string& target() const { return target_; }
  bool ok() const { return coordinator_ > 0; }
  // The gaitforge CLI pointed at this coordinator.
  CommandResult Cli(const std::string& args) const;

 private:
  std::string dir_, db_, target_;
  pid_t coordinator_ = -1;
  std::vector<pid_t> workers_;
};

}  // namespace gaitforge::testing
