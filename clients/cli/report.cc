// `gaitforge report ID` and `gaitforge trajectory ID`: a study's figures, chosen by what
// its objective and robot offer (StudyReport), among them the paper_gait figures and the
// marker exports of its best gaits. The coordinator gives the genotypes; the simulations
// run in gaitforge-sim, the workers' own model build.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"
#include "robots/registry.h"
#include "services/core/objective_catalog.h"
#include "services/recording/recording.h"

namespace gaitforge::cli {

int RunPlotScript(const std::vector<std::string>& args);

namespace {

std::string GenesArg(const v1::Individual& ind) {
  std::vector<std::string> g;
  for (double x : ind.genes()) g.push_back(absl::StrFormat("%.17g", x));
  return absl::StrJoin(g, ",");
}


// The study's robot as a gaitforge-sim --robot: the descriptor the study carries (written
// to a file named by its content), its built-in robot, or the built-in robot its objective
// is bound to (a robot's own objective name: the catalog's gait_robot or calibrates); ""
// when none.
std::string StudyRobot(const v1::ObjectiveSpec& objective) {
  if (!objective.robot_descriptor().empty()) {
    const std::string path =
        (std::filesystem::temp_directory_path() /
         ("gaitforge-robot-" + recording::ContentHash(objective.robot_descriptor(), "").substr(0, 16) +
          ".yaml"))
            .string();
    if (!std::filesystem::exists(path)) std::ofstream(path) << objective.robot_descriptor();
    return path;
  }
  if (!objective.robot().empty()) return objective.robot();
  const core::ObjectiveInfo* info = core::FindObjective(objective.name());
  return info ? (info->gait_robot.empty() ? info->calibrates : info->gait_robot) : "";
}

// The study's model as gaitforge-sim flags: its robot, the objective's `set` overrides (a
// corrected model), its timestep and settling cycles. `timestep_s` gets the step the study
// ran at (0 when it used the model file's own).
std::vector<std::string> StudyModelFlags(const v1::ObjectiveSpec& objective, double* timestep_s) {
  std::vector<std::string> flags;
  if (const std::string robot = StudyRobot(objective); !robot.empty())
    flags.insert(flags.end(), {"--robot", robot});
  std::string set;
  if (auto it = objective.options().find("set"); it != objective.options().end()) set = it->second;
  *timestep_s = 0;
  if (auto it = objective.params().find("timestep_ms"); it != objective.params().end()) {
    *timestep_s = it->second * 1e-3;
    absl::StrAppend(&set, set.empty() ? "" : ",",
                    absl::StrFormat("simulation.timestep_s=%.17g", *timestep_s));
  }
  if (!set.empty()) flags.insert(flags.end(), {"--set", set});
  if (auto it = objective.params().find("settle_cycles"); it != objective.params().end())
    flags.insert(flags.end(), {"--settle", absl::StrFormat("%d", static_cast<int>(it->second))});
  return flags;
}

std::vector<std::string> Concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The model file's timestep, as the objective catalog states it (timestep_ms's default,
// which the worker takes from the robot's descriptor).
double ModelTimestepS(const std::string& objective) {
  if (const core::ObjectiveInfo* info = core::FindObjective(objective)) {
    for (const auto& p : info->params)
      if (p.name == "timestep_ms") return p.default_value * 1e-3;
  }
  return 1e-3;
}

// The gait's distance per cycle (mean of 10 cycles) at its own period, at `timestep_s`,
// as a JSON object; empty on failure.
std::string TimestepCheck(const std::string& sim, const std::string& genes,
                          const v1::ObjectiveSpec& objective, double timestep_s) {
  v1::ObjectiveSpec at = objective;
  (*at.mutable_params())["timestep_ms"] = timestep_s * 1e3;
  double ignored = 0;
  std::string out;
  if (RunCapture(Concat({sim, "period-sweep", "--genes", genes, "--scales", "1,1,1",
                         "--cycles", "10"},
                        StudyModelFlags(at, &ignored)),
                 &out) != 0)
    return "";
  return absl::StrFormat("{\"timestep_s\": %.17g, \"result\": %s}", timestep_s, out);
}

}  // namespace

absl::StatusOr<v1::GetHallOfFameResponse> Hof(v1::StudyService::Stub& stub, const std::string& id,
                                              int generation, const GlobalOptions& g) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHallOfFameRequest req;
  req.set_study_id(id);
  if (generation >= 0) req.set_generation(generation);
  v1::GetHallOfFameResponse resp;
  grpc::Status s = stub.GetHallOfFame(&ctx, req, &resp);
  if (!s.ok()) return absl::Status(static_cast<absl::StatusCode>(s.error_code()), s.error_message());
  return resp;
}

int HofError(const absl::Status& s, const std::string& what) {
  return ReportRpcError(grpc::Status(static_cast<grpc::StatusCode>(s.code()),
                                     std::string(s.message())),
                        what);
}

int RankedGait(const GlobalOptions& g, const std::string& id, int generation, int rank,
               const std::string& what, v1::Individual* gait, v1::StudySummary* study) {
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  auto hof = Hof(conn->study(), id, generation, g);
  if (!hof.ok()) return HofError(hof.status(), what + " " + id);
  if (rank < 0 || rank >= hof->entries_size()) {
    std::cerr << "gaitforge: --rank = " << rank << " is out of range [0, "
              << hof->entries_size() - 1 << "]\n";
    return kNotFound;
  }
  *gait = hof->entries(rank).individual();
  if (grpc::Status s = FetchStudy(conn->study(), g, id, study); !s.ok())
    return ReportRpcError(s, what + " " + id);
  return kOk;
}

int PaperGaitReport(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                    const std::string& out_dir, const GlobalOptions& g, int top,
                    std::vector<std::string>* written) {
  const std::string& id = study.study_id();
  auto hof = Hof(stub, id, -1, g);
  if (!hof.ok()) return HofError(hof.status(), "report " + id);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string sim = SiblingBinary("gaitforge-sim");
  const v1::ObjectiveSpec& objective = study.spec().objective();
  double timestep_s = 0;
  const std::vector<std::string> model = StudyModelFlags(objective, &timestep_s);
  if (timestep_s == 0) timestep_s = ModelTimestepS(objective.name());
  std::string json = "{\n\"study_id\": \"" + id + "\",\n\"gaits\": [";
  int n = 0;
  for (const auto& e : hof->entries()) {
    if (n >= top) break;
    if (!e.individual().evaluation().valid()) continue;
    std::string sweep;
    const int code = RunCapture(Concat({sim, "period-sweep", "--genes", GenesArg(e.individual()),
                                        "--scales", "0.5,2,13", "--cycles", "10"},
                                       model),
                                &sweep);
    if (code != 0) {
      std::cerr << "gaitforge: gaitforge-sim period-sweep failed (exit " << code << ")\n";
      return kFailed;
    }
    std::vector<std::string> checks;
    for (double f : {1.0, 0.5, 0.25}) {
      const std::string c = TimestepCheck(sim, GenesArg(e.individual()), objective, f * timestep_s);
      if (c.empty()) {
        std::cerr << "gaitforge: gaitforge-sim period-sweep (timestep check) failed\n";
        return kFailed;
      }
      checks.push_back(c);
    }
    std::vector<std::string> genes;
    for (double x : e.individual().genes()) genes.push_back(absl::StrFormat("%.17g", x));
    absl::StrAppend(&json, n ? ",\n" : "\n",
                    absl::StrFormat("{\"rank\": %d, \"generation\": %d, \"member\": %d, "
                                    "\"fitness\": %.17g, \"genes\": [%s],\n \"period_sweep\": %s,\n"
                                    " \"timestep_check\": [%s]}",
                                    e.rank(), e.individual().generation(),
                                    e.individual().member(),
                                    e.individual().evaluation().fitness(),
                                    absl::StrJoin(genes, ", "), sweep,
                                    absl::StrJoin(checks, ", ")));
    if (n == 0) {
      const std::string csv = out_dir + "/" + id + "-best-trajectory.csv";
      // Markers are sampled on steps: 100 Hz, or the nearest rate whose interval is a whole
      // number of the study's steps.
      const double rate = 1.0 / (std::max(1.0, std::round(0.01 / timestep_s)) * timestep_s);
      std::string ignored;
      if (RunCapture(Concat({sim, "trajectory", "--genes", GenesArg(e.individual()), "--out",
                             csv, "--cycles", "3", "--rate", absl::StrFormat("%.17g", rate)},
                            model),
                     &ignored) == 0)
        written->push_back(csv);
    }
    ++n;
  }
  std::string wave;
  if (int code = RunCapture(
          Concat({sim, "wave", "--periods", "0.2,2.0,19", "--cycles", "10"}, model), &wave);
      code != 0) {
    std::cerr << "gaitforge: gaitforge-sim wave failed (exit " << code << ")\n";
    return kFailed;
  }
  absl::StrAppend(&json, "],\n\"wave\": ", wave, "\n}\n");
  const std::string path = out_dir + "/" + id + "-report.json";
  std::ofstream(path) << json;
  written->push_back(path);
  std::string figures;
  if (RunPlotScript({"paper-gait", "--report", path, "--out-prefix", out_dir + "/" + id}) != 0) {
    std::cerr << "gaitforge: drawing the paper_gait figures failed\n";
    return kFailed;
  }
  for (const char* f : {"-gaits.svg", "-period-sweep.svg", "-wave.svg"})
    written->push_back(out_dir + "/" + id + f);
  return kOk;
}

int CmdTrajectory(const GlobalOptions& g, const std::vector<std::string>& args, int rank,
                  int generation, const std::string& out, double rate, int cycles) {
  if (args.size() != 1 || out.empty()) {
    std::cerr << "gaitforge: usage: gaitforge trajectory STUDY_ID --output FILE.csv "
                 "[--rank R] [--generation G] [--rate HZ] [--cycles N]\n";
    return kUsage;
  }
  // The gait, and the study's own model (a corrected model's `set`, its timestep and
  // settling).
  v1::Individual gait;
  v1::StudySummary study;
  int code = RankedGait(g, args[0], generation, rank, "trajectory", &gait, &study);
  if (code != kOk) return code;
  double timestep_s = 0;
  std::string printed;
  code = RunCapture(Concat({SiblingBinary("gaitforge-sim"), "trajectory", "--genes",
                            GenesArg(gait), "--out", out, "--rate",
                            absl::StrFormat("%.17g", rate), "--cycles", std::to_string(cycles)},
                           StudyModelFlags(study.spec().objective(), &timestep_s)),
                    &printed);
  if (code != 0) return code == 2 ? kUsage : kFailed;
  std::cout << out << "\n";
  return kOk;
}

int StudyReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                const GlobalOptions& g, std::vector<std::string>* written) {
  const core::ObjectiveInfo* info = core::FindObjective(study.spec().objective().name());
  if (!info) return kOk;
  if (info->name == "robot.tracking") {
    if (!g.json) std::cerr << "tracking the paths with the descriptor's and the best parameters...\n";
    return TrackingReport(conn, study, out_dir, g, written);
  }
  if (info->calibration) {
    if (!g.json) std::cerr << "evaluating the fit on training and held-out recordings...\n";
    return CalibrationReport(conn, study, out_dir, g, written);
  }
  const robots::RobotDescriptor* robot =
      info->gait_robot.empty() ? nullptr : robots::FindRobot(info->gait_robot);
  if (robot && std::count(robot->figures.begin(), robot->figures.end(), "paper_gait")) {
    if (!g.json) std::cerr << "drawing the paper_gait figures of " << robot->name << "...\n";
    return PaperGaitReport(conn.study(), study, out_dir, g, 3, written);
  }
  return kOk;
}

int CmdReport(const GlobalOptions& g, const std::vector<std::string>& args,
              const std::string& out_dir) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge report STUDY_ID [--out DIR]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  std::vector<std::string> written;
  v1::StudySummary study;
  grpc::Status s = FetchStudy(conn->study(), g, args[0], &study);
  if (!s.ok()) return ReportRpcError(s, "report " + args[0]);
  code = PlotStudy(conn->study(), args[0], out_dir, g, &written);
  if (code == kOk) code = StudyReport(*conn, study, out_dir, g, &written);
  for (const auto& f : written) std::cout << f << "\n";
  return code;
}

}  // namespace gaitforge::cli
