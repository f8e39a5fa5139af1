// `gaitforge dashboard`: the web dashboard of the local database (docs/dashboard.md). A
// coordinator that holds the database and serves one already (a running `gaitforge local`)
// is named; otherwise a read-only coordinator serves it until Ctrl-C.
#include <signal.h>

#include <iostream>

#include "clients/cli/cli.h"
#include "clients/cli/processes.h"

namespace gaitforge::cli {

int CmdDashboard(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (!args.empty() || !g.coordinator.empty()) {
    std::cerr << "gaitforge: usage: gaitforge dashboard [--db FILE] [--dashboard HOST:PORT]; a "
                 "remote coordinator serves its own (gaitforge-coordinator --dashboard-listen)\n";
    return kUsage;
  }
  if (g.dashboard.empty()) {
    std::cerr << "gaitforge: dashboard: --dashboard off leaves nothing to serve\n";
    return kUsage;
  }
  if (auto holder = FindDbHolder(g.db); holder && !holder->dashboard.empty()) {
    std::cout << holder->dashboard << "\n";
    std::cerr << "gaitforge: served by the coordinator that holds " << g.db << " (pid "
              << holder->pid << ")\n";
    return kOk;
  }
  // Signals wait for sigwait below, in this thread, rather than killing the process: the
  // read-only coordinator is then stopped by the connection's destructor.
  sigset_t sigs;
  sigemptyset(&sigs);
  sigaddset(&sigs, SIGINT);
  sigaddset(&sigs, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &sigs, nullptr);
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  std::cout << conn->dashboard_url() << std::endl;
  std::cerr << "gaitforge: serving the dashboard of " << g.db << " (read-only); Ctrl-C stops\n";
  int sig = 0;
  sigwait(&sigs, &sig);
  return kOk;
}

}  // namespace gaitforge::cli
