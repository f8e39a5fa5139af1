// The embedded default: `gaitforge local SPEC` and `gaitforge resume ID` without a
// --coordinator start a coordinator and N worker processes on this machine, over a SQLite
// file under ./runs/, run the study to its end and leave everything queryable.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <iostream>

#include "clients/cli/cli.h"
#include "clients/cli/processes.h"

namespace gaitforge::cli {

int LoadSpec(const std::string& path, v1::StudySpec* out);

namespace {

char interrupt_note[1024];
size_t interrupt_note_size = 0;

void OnInterrupt(int) {
  (void)!write(STDERR_FILENO, interrupt_note, interrupt_note_size);
  _exit(130);
}

// On Ctrl-C, says what happened and how to continue, and exits 130. The coordinator and
// the workers get the signal too (or SIGTERM as this process ends) and stop cleanly; the
// study stays `running` in the database, every committed generation kept.
void ExplainInterrupt(const GlobalOptions& g, const std::string& id) {
  const std::string note = "\ngaitforge: interrupted; study " + id + " is stored in " + g.db +
                           " up to its last committed generation: " + ContinueHint(g, id) +
                           "\n";
  interrupt_note_size = std::min(note.size(), sizeof interrupt_note);
  std::memcpy(interrupt_note, note.data(), interrupt_note_size);
  struct sigaction sa = {};
  sa.sa_handler = OnInterrupt;
  sigaction(SIGINT, &sa, nullptr);
}

// The study as the coordinator has it (empty summary if the call fails).
v1::StudySummary Summary(Connection& conn, const std::string& id, const GlobalOptions& g) {
  v1::StudySummary s;
  (void)FetchStudy(conn.study(), g, id, &s);
  return s;
}

}  // namespace

int RunWithLocalWorkers(const GlobalOptions& g, Connection& conn, int workers, int threads,
                        const std::string& out_dir,
                        const std::function<std::string(v1::StudyService::Stub&)>& start,
                        int* start_code) {
  const std::string logs = LogsDir(g);
  std::string id = start(conn.study());
  if (id.empty()) return *start_code;
  ExplainInterrupt(g, id);
  std::vector<pid_t> pids = StartLocalWorkers(g, conn.target(), workers, threads);
  if (!g.json)
    std::cerr << "study " << id << ": " << workers << " local worker(s) x " << threads
              << " thread(s); database " << g.db << "; logs in " << logs << "/\n";
  if (!g.json && !conn.dashboard_url().empty())
    std::cerr << "dashboard: " << conn.dashboard_url() << "#/study/" << id << "\n";
  const int code = WatchUntilDone(conn.study(), id, g, 30 * 24 * 3600.0);
  // Workers drain their batch to the coordinator; without one there is nothing to drain.
  for (pid_t p : pids) Stop(p, code == kUnavailable ? 1 : 10);
  if (code == kOk && !out_dir.empty()) {
    std::vector<std::string> figures;
    const v1::StudySummary study = Summary(conn, id, g);
    if (PlotStudy(conn.study(), id, out_dir, g, &figures) == kOk)
      StudyReport(conn, study, out_dir, g, &figures);
    if (!g.json)
      for (const auto& f : figures) std::cerr << "wrote " << f << "\n";
  }
  if (!g.json && code == kOk && !out_dir.empty())
    std::cerr << "next: gaitforge history " << id << " | gaitforge hof " << id
              << " | gaitforge show " << id << "\n";
  return code;
}

std::function<std::string(v1::StudyService::Stub&)> CreateStudyStart(const GlobalOptions& g,
                                                                    v1::StudySpec spec,
                                                                    std::string what, int* code) {
  return [&g, spec = std::move(spec), what = std::move(what), code](v1::StudyService::Stub& stub) {
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    v1::CreateStudyRequest req;
    *req.mutable_spec() = spec;
    v1::CreateStudyResponse resp;
    grpc::Status s = stub.CreateStudy(&ctx, req, &resp);
    if (!s.ok()) {
      *code = ReportRpcError(s, what);
      return std::string();
    }
    return resp.study().study_id();
  };
}

std::vector<pid_t> StartLocalWorkers(const GlobalOptions& g, const std::string& target, int workers,
                                     int threads) {
  const std::string logs = LogsDir(g);
  std::vector<pid_t> pids;
  for (int i = 0; i < workers; ++i) {
    const std::string log = logs + "/worker-" + std::to_string(i) + ".log";
    pids.push_back(Spawn({SiblingBinary("gaitforge-worker"), "--coordinator", target, "--threads",
                          std::to_string(threads), "--worker-id",
                          "local-" + std::to_string(i) + "-" + std::to_string(getpid())},
                         log));
  }
  return pids;
}

int CmdLocal(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
             int threads, const std::string& out_dir) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge local SPEC.yaml [--workers N] [--threads T]\n";
    return kUsage;
  }
  if (!g.coordinator.empty()) {
    std::cerr << "gaitforge: local runs its own coordinator; use 'submit' with --coordinator\n";
    return kUsage;
  }
  v1::CreateStudyRequest req;
  if (int c = LoadSpec(args[0], req.mutable_spec()); c) return c;
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  if (int c = UploadSpecRecordings(*conn, args[0], req.mutable_spec(), g); c) return c;
  int start_code = kOk;
  return RunWithLocalWorkers(g, *conn, workers, threads, out_dir,
                             CreateStudyStart(g, req.spec(), "create study from " + args[0],
                                              &start_code),
                             &start_code);
}

int CmdResume(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
              int threads, const std::string& out_dir) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge resume STUDY_ID\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  int start_code = kOk;
  auto resume = [&](v1::StudyService::Stub& stub) -> std::string {
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    v1::ResumeStudyRequest req;
    req.set_study_id(args[0]);
    v1::StudySummary resp;
    grpc::Status s = stub.ResumeStudy(&ctx, req, &resp);
    if (!s.ok()) {
      start_code = ReportRpcError(s, "resume " + args[0]);
      return "";
    }
    return resp.study_id();
  };
  if (!g.coordinator.empty()) {
    // A remote coordinator's workers do the work; just resume and report.
    if (resume(conn->study()).empty()) return start_code;
    std::cout << args[0] << " running\n";
    return kOk;
  }
  return RunWithLocalWorkers(g, *conn, workers, threads, out_dir, resume, &start_code);
}

}  // namespace gaitforge::cli
