#include "clients/cli/processes.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace gaitforge::cli {

pid_t Spawn(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t parent = getpid();
  pid_t pid = fork();
  if (pid != 0) return pid;
  // Child: own process group member of ours; signals from the terminal reach it too.
  // A private coordinator or worker must not outlive the command that started it, however
  // that command ends (kill -9, OOM killer): an orphaned coordinator would keep the
  // database locked. SIGTERM shuts it down cleanly; a worker drains. (Linux: the signal
  // comes when the forking thread ends; Spawn is called from the main thread only.)
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(1);  // the parent died before prctl
  int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd >= 0) {
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
  }
  int devnull = open("/dev/null", O_RDONLY);
  if (devnull >= 0) dup2(devnull, 0);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // A private coordinator takes no tokens from the user's environment.
  for (const char* v : {"GAITFORGE_CLIENT_TOKEN", "GAITFORGE_WORKER_TOKEN", "GAITFORGE_ADMIN_TOKEN"})
    unsetenv(v);
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  execvp(args[0], args.data());
  _exit(127);
}

void Stop(pid_t pid, double grace_s) {
  if (pid <= 0) return;
  kill(pid, SIGTERM);
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(static_cast<int>(grace_s * 1000));
  while (std::chrono::steady_clock::now() < until) {
    int status;
    if (waitpid(pid, &status, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  int status;
  waitpid(pid, &status, 0);
}

int WaitForPortFile(const std::string& path, pid_t pid, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(static_cast<int>(timeout_s * 1000));
  while (std::chrono::steady_clock::now() < until) {
    std::ifstream in(path);
    int port = 0;
    if (in >> port && port > 0) return port;
    int status;
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return -1;
}

std::optional<DbHolder> FindDbHolder(const std::string& db) {
  std::ifstream lock(db + ".lock");
  DbHolder h;
  if (!(lock >> h.pid) || h.pid <= 0) return std::nullopt;
  lock >> h.address;
  h.dashboard = DashboardLine(lock);
  // Alive (not a zombie nobody reaped), and a coordinator (a recycled pid would be another
  // program): /proc/PID/stat is "PID (COMM) STATE ...", COMM cut to 15 characters.
  std::ifstream stat("/proc/" + std::to_string(h.pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return std::nullopt;
  const size_t open = line.find('('), close = line.rfind(')');
  if (open == std::string::npos || close == std::string::npos || close + 2 >= line.size())
    return std::nullopt;
  const std::string comm = line.substr(open + 1, close - open - 1);
  const char state = line[close + 2];
  if (comm != std::string("gaitforge-coordinator").substr(0, 15) || state == 'Z' ||
      state == 'X')
    return std::nullopt;
  return h;
}

std::string DashboardLine(std::istream& in) {
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("dashboard ", 0) == 0) return line.substr(10);
  return "";
}

pid_t StartCoordinator(const std::string& db, bool read_only, const std::string& log_dir,
                       std::string* target, std::string* error, const std::string& dashboard,
                       std::string* dashboard_url) {
  std::error_code ec;
  std::filesystem::create_directories(log_dir, ec);
  const std::string port_file =
      (std::filesystem::path(log_dir) / ("coordinator-" + std::to_string(getpid()) + ".port"))
          .string();
  std::filesystem::remove(port_file, ec);
  std::vector<std::string> argv = {SiblingBinary("gaitforge-coordinator"), "--listen",
                                   "127.0.0.1:0", "--db", db, "--port-file", port_file};
  if (read_only) argv.push_back("--read-only");
  if (!dashboard.empty()) argv.insert(argv.end(), {"--dashboard-listen", dashboard});
  const std::string log = (std::filesystem::path(log_dir) / "coordinator.log").string();
  // The log is shared with earlier (and perhaps still stopping) coordinators on the same
  // directory: the words of this one start here.
  std::error_code size_error;  // no log yet: start at 0
  std::uintmax_t log_start = std::filesystem::file_size(log, size_error);
  if (size_error) log_start = 0;
  pid_t pid = Spawn(argv, log);
  if (pid < 0) {
    *error = "cannot start gaitforge-coordinator";
    return -1;
  }
  const int port = WaitForPortFile(port_file, pid, 30);
  if (port > 0 && dashboard_url) {
    std::ifstream in(port_file);
    *dashboard_url = DashboardLine(in);
  }
  std::filesystem::remove(port_file, ec);
  if (port < 0) {
    Stop(pid, 1);
    // The coordinator's last words say why (a locked database, a bad path, ...): its
    // "gaitforge-coordinator: ..." line, not a line another coordinator logged meanwhile
    // (one that was told to stop a moment ago logs "stopped" as it releases the database).
    std::ifstream in(log);
    in.seekg(static_cast<std::streamoff>(log_start));
    std::string line, last, fail;
    while (std::getline(in, line)) {
      if (!line.empty()) last = line;
      if (line.rfind("gaitforge-coordinator: ", 0) == 0) fail = line;
    }
    *error = "gaitforge-coordinator did not start: " + (fail.empty() ? last : fail) +
             " (log: " + log + ")";
    return -1;
  }
  *target = "127.0.0.1:" + std::to_string(port);
  return pid;
}

}  // namespace gaitforge::cli
