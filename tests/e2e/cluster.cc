#include "tests/e2e/cluster.h"

#include <gtest/gtest.h>
#include <stdio.h>
#include <sys/wait.h>

#include <filesystem>

#include "clients/cli/processes.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {

std::string Bin(const std::string& name) { return std::string(GAITFORGE_BIN_DIR) + "/" + name; }

CommandResult RunCommand(const std::string& command_line) {
  static int counter = 0;
  const std::string err_file = (std::filesystem::temp_directory_path() /
                                ("gaitforge-e2e-err-" + std::to_string(getpid()) + "-" +
                                 std::to_string(counter++)))
                                   .string();
  CommandResult r;
  FILE* p = popen((command_line + " 2>" + err_file).c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = ReadFile(err_file);
  std::filesystem::remove(err_file);
  return r;
}

LocalCluster::LocalCluster(const std::string& dir, const std::string& db,
                           const std::vector<std::string>& extra_flags)
    : dir_(dir), db_(db) {
  const std::string port_file = dir + "/coordinator.port";
  std::filesystem::remove(port_file);
  std::vector<std::string> argv = {Bin("gaitforge-coordinator"), "--listen", "127.0.0.1:0",
                                   "--db", db, "--port-file", port_file, "--log-level", "warn"};
  argv.insert(argv.end(), extra_flags.begin(), extra_flags.end());
  coordinator_ = cli::Spawn(argv, dir + "/coordinator.log");
  const int port = cli::WaitForPortFile(port_file, coordinator_, 30);
  if (port < 0) {
    ADD_FAILURE() << "coordinator did not start:\n" << ReadFile(dir + "/coordinator.log");
    coordinator_ = -1;
    return;
  }
  target_ = "127.0.0.1:" + std::to_string(port);
}

LocalCluster::~LocalCluster() {
  StopWorkers();
  StopCoordinator();
}

void LocalCluster::StartWorkers(int n, int threads) {
  for (int i = 0; i < n; ++i) {
    const std::string id = "w" + std::to_string(workers_.size());
    workers_.push_back(cli::Spawn({Bin("gaitforge-worker"), "--coordinator", target_,
                                   "--threads", std::to_string(threads), "--worker-id", id,
                                   "--log-level", "warn"},
                                  dir_ + "/" + id + ".log"));
  }
}

void LocalCluster::StopWorkers() {
  for (pid_t p : workers_) cli::Stop(p, 10);
  workers_.clear();
}

void LocalCluster::StopCoordinator() {
  if (coordinator_ > 0) cli::Stop(coordinator_, 10);
  coordinator_ = -1;
}

CommandResult LocalCluster::Cli(const std::string& args) const {
  return RunCommand(Bin("gaitforge") + " --coordinator " + target_ + " " + args);
}

}  // namespace gaitforge::testing
