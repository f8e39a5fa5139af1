#pragma once
// Real processes on loopback: a gaitforge-coordinator, gaitforge-worker processes and
// gaitforge CLI invocations, for end-to-end tests.
#include <sys/types.h>

#include <string>
#include <vector>

namespace gaitforge::testing {

std::string Bin(const std::string& name);

// Rows of a query on a SQLite file, each as "col|col|" text (NULL for null), for exact
// comparison between databases.
std::vector<std::string> Rows(const std::string& db, const std::string& sql);

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs a command line through /bin/sh and captures its output.
CommandResult RunCommand(const std::string& command_line);

// The id of the first study `cli` (a "gaitforge --db DB" command line) lists once it has
// committed at least `generations` generations; "" after 120 s.
std::string WaitForGenerations(const std::string& cli, int generations);

class TempDir;
// Submits spec `text` to a LocalCluster on db in dir, with `workers` workers, and watches it
// to the end (a failure unless it completes). Returns the study's id ("" if none started).
std::string RunClusterStudy(const TempDir& dir, const std::string& db, const std::string& text,
                            int workers);
// Runs spec `text` with `gaitforge local` in dir on 2 workers; its stderr must hold
// `expect`. Returns the study's id ("" and a failure if none).
std::string RunLocal(const TempDir& dir, const std::string& text, const std::string& expect);

// GET http://127.0.0.1:port/path; returns the body ("" on failure).
std::string HttpGet(int port, const std::string& path);

class LocalCluster {
 public:
  // Starts a coordinator on db (port 0 on 127.0.0.1) logging into dir.
  LocalCluster(const std::string& dir, const std::string& db,
               const std::vector<std::string>& extra_flags = {});
  ~LocalCluster();
  void StartWorkers(int n, int threads = 1, const std::vector<std::string>& extra_flags = {});
  void StopWorkers();
  void StopCoordinator();
  // SIGKILL: the coordinator dies at once, as on a lost node.
  void KillCoordinator();
  const std::string& target() const { return target_; }
  int metrics_port() const { return metrics_port_; }
  bool ok() const { return coordinator_ > 0; }
  // The gaitforge CLI pointed at this coordinator.
  CommandResult Cli(const std::string& args) const;

 private:
  std::string dir_, db_, target_;
  pid_t coordinator_ = -1;
  int metrics_port_ = -1;
  std::vector<pid_t> workers_;
};

}  // namespace gaitforge::testing
