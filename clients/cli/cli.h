#pragma once
// Shared pieces of the gaitforge command-line client.
#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/diagnosis.grpc.pb.h"
#include "gaitforge/v1/study.grpc.pb.h"
#include "services/diagnosis/plan.h"

namespace gaitforge::cli {

// Exit codes scripts can rely on (docs/cli.md).
enum ExitCode {
  kOk = 0,
  kStudyNotCompleted = 1,  // a watched study ended failed or cancelled
  kUsage = 2,              // bad flags or bad input (spec errors)
  kNotFound = 3,           // unknown study id or generation
  kUnavailable = 4,        // no coordinator reachable
  kFailed = 5,             // any other error
  kDenied = 6,             // missing or wrong token (UNAUTHENTICATED, PERMISSION_DENIED)
};

struct GlobalOptions {
  std::string coordinator;       // empty: embedded mode over `db`
  std::string db = "runs/gaitforge.db";
  double timeout_s = 30;         // deadline of every unary call
  bool json = false;
  bool csv = false;
  std::string tls_ca, tls_cert, tls_key;  // TLS to --coordinator
  std::string token;                      // bearer token (client role), from a file or env
  // Where a coordinator this process starts serves the web dashboard (HOST:PORT, port 0:
  // any free one); empty: none. Set for the commands that run studies (local, resume,
  // diagnose) and `dashboard`.
  std::string dashboard;
};

// Where embedded coordinators and workers log: logs/ in the database's folder.
std::string LogsDir(const GlobalOptions& g);

// The token every call of this process carries (set once by main).
void SetCallToken(const std::string& token);

// A connection to a coordinator: a given address, or an embedded read-only coordinator
// started on the database file for the life of this object.
class Connection {
 public:
  // Embedded mode: a write, or a `live` read, goes to the loopback coordinator that already
  // holds the database (a running `gaitforge local`) if there is one, instead of failing
  // on its lock or reading the file beside it.
  static std::unique_ptr<Connection> Open(const GlobalOptions& g, bool writable, std::string* error,
                                          bool live = false);
  std::shared_ptr<grpc::Channel> channel() const { return channel_; }
  ~Connection();
  v1::StudyService::Stub& study() { return *study_; }
  const std::string& target() const { return target_; }
  pid_t embedded_pid() const { return pid_; }
  // True when talking to the coordinator that holds the database (see Open).
  bool shared() const { return shared_; }
  // The URL of the coordinator's web dashboard ("" when it serves none, or is remote).
  const std::string& dashboard_url() const { return dashboard_url_; }

 private:
  std::string target_;
  pid_t pid_ = 0;
  bool shared_ = false;
  std::string dashboard_url_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::StudyService::Stub> study_;
};

// Opens a connection or prints why not and sets *code (kNotFound: no local database yet;
// kUnavailable otherwise).
std::unique_ptr<Connection> Connect(const GlobalOptions& g, bool writable, int* code,
                                    bool live = false);
// Embedded mode without a coordinator holding the database: its `running` studies are
// interrupted (their coordinator stopped or was killed) and wait for `gaitforge resume`.
bool Unheld(const GlobalOptions& g);
// The state as shown: "interrupted" for a running study when `unheld`.
std::string ShownState(v1::StudyState s, bool unheld);
// How to continue study `id` after its coordinator went away.
std::string ContinueHint(const GlobalOptions& g, const std::string& id);
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target);
void SetDeadline(grpc::ClientContext& ctx, double seconds);
// GetStudy of `id` with the call deadline.
grpc::Status FetchStudy(v1::StudyService::Stub& stub, const GlobalOptions& g,
                        const std::string& id, v1::StudySummary* out);
// Prints the error and returns the matching exit code.
int ReportRpcError(const grpc::Status& s, const std::string& what);
std::string ToJson(const google::protobuf::Message& m);
// `s` as a JSON string literal (quotes, backslashes and newlines escaped).
std::string JsonQuote(const std::string& s);
std::string StateName(v1::StudyState s);
std::string FormatDuration(double seconds);
// "invalid N (REASON)": the invalid members of a generation and their commonest reason,
// cut to 40 characters when `short_reason` (a progress bar's line).
std::string InvalidText(int invalid, const std::string& reason, bool short_reason);
// A progress bar on stderr, redrawn in place: "\r[#####.....] line" (frac in [0, 1]).
void DrawProgressBar(double frac, const std::string& line);

// Command entry points: args are what follows the command name.
int CmdSubmit(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdWatch(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdList(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdShow(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdHof(const GlobalOptions& g, const std::vector<std::string>& args, int generation,
           bool has_generation);
int CmdHistory(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdIndividuals(const GlobalOptions& g, const std::vector<std::string>& args, int generation);
int CmdResume(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
              int threads, const std::string& out_dir);
int CmdCancel(const GlobalOptions& g, const std::vector<std::string>& args);
// grpc.health.v1 Check of --coordinator: prints SERVING (exit 0) or why not (exit 4).
int CmdHealth(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdLocal(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
             int threads, const std::string& out_dir);
// `dashboard`: the web dashboard of the local database until Ctrl-C (dashboard.cc).
int CmdDashboard(const GlobalOptions& g, const std::vector<std::string>& args);

int CmdPlot(const GlobalOptions& g, const std::vector<std::string>& args,
            const std::string& out_dir);
// Writes the study's figures into out_dir; appends the files written.
int PlotStudy(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
              const GlobalOptions& g, std::vector<std::string>* written);

// Calls fn(generation, member) for every evaluated member (carried elites left out) of the
// study's completed generations, in order; false when listing a generation fails.
bool ForEachMember(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                   const GlobalOptions& g,
                   const std::function<void(int, const v1::Individual&)>& fn);

// Every evaluated member (ForEachMember) as a JSON array of {generation, member, genes,
// valid, fitness, violation, metrics}; false when listing fails.
bool WriteMembersJson(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                      const GlobalOptions& g, std::ostream& out);

// A multi-objective (nsga2) study's Pareto figure into out_dir: every member's first two
// objectives and the final front (clients/python/gaitforge_plot.py pareto); nothing for
// another engine. Appends the files.
int PlotPareto(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
               const GlobalOptions& g, std::vector<std::string>* written);

// A factorial sweep's (two factors or more) statistics and box plot into out_dir
// (clients/python/gaitforge_factorial.py); nothing for another study. Appends the files.
int PlotFactorial(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                  const std::string& out_dir, const GlobalOptions& g,
                  std::vector<std::string>* written);

int CmdReport(const GlobalOptions& g, const std::vector<std::string>& args,
              const std::string& out_dir);
// A study's hall of fame (latest, or generation >= 0), and its error as the exit code.
absl::StatusOr<v1::GetHallOfFameResponse> Hof(v1::StudyService::Stub& stub, const std::string& id,
                                              int generation, const GlobalOptions& g);
int HofError(const absl::Status& s, const std::string& what);
// Hall-of-fame entry `rank` of study `id` (latest generation, or generation >= 0) and the
// study; kOk, or the exit code after printing why not (`what` names the command).
int RankedGait(const GlobalOptions& g, const std::string& id, int generation, int rank,
               const std::string& what, v1::Individual* gait, v1::StudySummary* study);
int CmdExport(const GlobalOptions& g, const std::vector<std::string>& args, int rank,
              int generation, const std::string& out, double rate, int cycles);
int CmdTrajectory(const GlobalOptions& g, const std::vector<std::string>& args, int rank,
                  int generation, const std::string& out, double rate, int cycles);
// The figures a study's objective and robot offer, after its fitness curve: a calibration's
// report (CalibrationReport) when the objective calibrates a robot; the paper_gait figures
// when its robot's descriptor lists them (`figures`, docs/robots.md); else none.
int StudyReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                const GlobalOptions& g, std::vector<std::string>* written);
// The paper_gait figures (gait diagrams, period sweep, travelling wave) for the
// study's `top` best gaits, and the best one's marker trajectory, into out_dir; every
// simulation with the study's own model (its objective's `set`, timestep_ms and
// settle_cycles). Each best gait is also re-run at half and a quarter of the timestep
// ("timestep_check"): the hopping robot's single-cycle fitness can be numerical luck.
int PaperGaitReport(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                    const std::string& out_dir, const GlobalOptions& g, int top,
                    std::vector<std::string>* written);
// `robots [NAME | FILE]`: the built-in robots, or one descriptor and what it offers (robots.cc).
int CmdRobots(const GlobalOptions& g, const std::vector<std::string>& args);
int CmdRecording(const GlobalOptions& g, const std::vector<std::string>& args,
                 const std::string& sidecar, const std::string& robot_file);
// Uploads every recording the spec names by file path (relative to the spec file) and puts
// its content hash in its place. Returns an exit code.
int UploadSpecRecordings(Connection& conn, const std::string& spec_path, v1::StudySpec* spec,
                         const GlobalOptions& g);

// The study's hall of fame into hof; kFailed (with a message) when it holds no valid result.
int BestOfStudy(Connection& conn, const std::string& id, const GlobalOptions& g,
                v1::GetHallOfFameResponse* hof);
// A recording the coordinator stores, downloaded into dir with its sidecar; "" on failure.
std::string DownloadRecording(Connection& conn, const std::string& hash, const std::string& dir,
                              const GlobalOptions& g);
// A robot.tracking study's report into out_dir (tracking_report.cc): each path tracked with
// the descriptor's parameters and with the study's best genes, a JSON of their errors and
// the tracking figure.
int TrackingReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                   const GlobalOptions& g, std::vector<std::string>* written);

// The calibration study's report into out_dir (calibration_report.cc).
int CalibrationReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                      const GlobalOptions& g, std::vector<std::string>* written);

// Waits for a stored diagnosis (progress on stderr unless --json), copies its files into
// out_root/NAME-diagnosis and prints it. `runner`: the coordinator runs diagnoses (else a
// running one is interrupted).
int AwaitDiagnosis(v1::DiagnosisService::Stub& stub, const std::string& id,
                   const std::string& out_root, const GlobalOptions& g, bool runner);
int CmdDiagnosis(const GlobalOptions& g, const std::vector<std::string>& args,
                 const std::string& out_root);
int CmdDiagnoses(const GlobalOptions& g, const std::vector<std::string>& args);
// `cancel ID` for a stored diagnosis (the fits it started are cancelled with it).
int CancelDiagnosis(Connection& conn, const std::string& id, const GlobalOptions& g);
int CmdDiagnose(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const std::string& out_dir);
// A diagnosis spec file, parsed, with defaults, checked (the robot from the recordings when
// it names none); an exit code on failure, the reason on stderr.
int ReadDiagnosisSpec(const std::string& path, v1::DiagnosisSpec* d);

// `gaitforge diagnose plan SPEC --report FILE` (diagnose_plan.cc); `output`: the plan's JSON
// ("": plan.json beside the report).
int CmdDiagnosePlan(const GlobalOptions& g, const std::vector<std::string>& args,
                    const diagnosis::plan::Options& p, const std::string& output);
// Starts workers against conn's coordinator, runs `start` (which returns the study id, or ""
// after printing an error and setting *start_code), watches the study to its end, then
// drains the workers; with a non-empty out_dir, draws the study's figures there.
int RunWithLocalWorkers(const GlobalOptions& g, Connection& conn, int workers, int threads,
                        const std::string& out_dir,
                        const std::function<std::string(v1::StudyService::Stub&)>& start,
                        int* start_code);
// A `start` for RunWithLocalWorkers: creates the study of `spec` and returns its id, or ""
// after printing the error (as `what`) and setting *code.
std::function<std::string(v1::StudyService::Stub&)> CreateStudyStart(const GlobalOptions& g,
                                                                    v1::StudySpec spec,
                                                                    std::string what, int* code);
// `validate ID`: a robust study's gaits over a fresh ensemble (validate.cc).
struct ValidateOptions {
  int members = 0;        // 0: four times the study's ensemble (at most 256)
  uint64_t seed = 0;      // 0: the study's ensemble seed + 1
  int top = 0;            // hall-of-fame gaits to validate; 0: all
  std::string gaits;      // a file of gaits instead of the hall of fame
  std::string from_calibration;  // a calibration whose model predicts them; "": the study's
};
int CmdValidate(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const ValidateOptions& v);
// Starts local worker processes against target (logs next to the database).
std::vector<pid_t> StartLocalWorkers(const GlobalOptions& g, const std::string& target, int workers,
                                     int threads);
std::string PlotScriptPath();

// Runs clients/python/gaitforge_plot.py with args; returns its exit code.
int RunPlotScript(const std::vector<std::string>& args);

// Streams progress of a study until it ends, drawing a progress bar on a terminal.
// Returns kOk if it completed.
int WatchUntilDone(v1::StudyService::Stub& stub, const std::string& id, const GlobalOptions& g,
                   double watch_timeout_s);

}  // namespace gaitforge::cli
