#pragma once
// Child processes of `gaitforge local`: the coordinator and the workers.
#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "services/core/subprocess.h"

namespace gaitforge::cli {

using core::RunCapture;
using core::SiblingBinary;

// Starts argv[0] with stdout and stderr appended to log_path. Returns the pid, or -1.
pid_t Spawn(const std::vector<std::string>& argv, const std::string& log_path);
// SIGTERM, then SIGKILL after grace_s; reaps the child.
void Stop(pid_t pid, double grace_s);
// Waits for the coordinator's --port-file; returns the port or -1 (child died or timeout).
int WaitForPortFile(const std::string& path, pid_t pid, double timeout_s);
// The live coordinator that holds db's write lock, from DB.lock ("PID\nHOST:PORT\n", the
// address once it serves); nullopt if that process is gone (killed, or stopped).
struct DbHolder {
  pid_t pid = 0;
  std::string address;    // empty while it starts
  std::string dashboard;  // its dashboard's URL ("dashboard URL" line), empty if none
};
std::optional<DbHolder> FindDbHolder(const std::string& db);
// Starts a coordinator on db, listening on loopback; returns its pid and "127.0.0.1:port".
// With `dashboard` (HOST:PORT) it also serves the web dashboard there; *dashboard_url gets
// its URL.
pid_t StartCoordinator(const std::string& db, bool read_only, const std::string& log_dir,
                       std::string* target, std::string* error,
                       const std::string& dashboard = "", std::string* dashboard_url = nullptr);
// The "dashboard URL" line of a coordinator's --port-file or lock file ("" if none).
std::string DashboardLine(std::istream& in);

}  // namespace gaitforge::cli
