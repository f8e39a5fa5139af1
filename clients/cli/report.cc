// `gaitforge report ID` and `gaitforge trajectory ID`: the caterpillar paper's figures and
// marker exports for a study's best gaits. The coordinator gives the genotypes; the
// simulations run in gaitforge-sim, the workers' own model build.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"

namespace gaitforge::cli {

int RunPlotScript(const std::vector<std::string>& args);

namespace {

std::string GenesArg(const v1::Individual& ind) {
  std::vector<std::string> g;
  for (double x : ind.genes()) g.push_back(absl::StrFormat("%.17g", x));
  return absl::StrJoin(g, ",");
}

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

}  // namespace

int CaterpillarReport(v1::StudyService::Stub& stub, const std::string& id,
                      const std::string& out_dir, const GlobalOptions& g, int top,
                      std::vector<std::string>* written) {
  auto hof = Hof(stub, id, -1, g);
  if (!hof.ok()) return HofError(hof.status(), "report " + id);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string sim = SiblingBinary("gaitforge-sim");
  std::string json = "{\n\"study_id\": \"" + id + "\",\n\"gaits\": [";
  int n = 0;
  for (const auto& e : hof->entries()) {
    if (n >= top) break;
    if (!e.individual().evaluation().valid()) continue;
    std::string sweep;
    const int code = RunCapture({sim, "period-sweep", "--genes", GenesArg(e.individual()),
                                 "--scales", "0.5,2,13", "--cycles", "10"},
                                &sweep);
    if (code != 0) {
      std::cerr << "gaitforge: gaitforge-sim period-sweep failed (exit " << code << ")\n";
      return kFailed;
    }
    std::vector<std::string> genes;
    for (double x : e.individual().genes()) genes.push_back(absl::StrFormat("%.17g", x));
    absl::StrAppend(&json, n ? ",\n" : "\n",
                    absl::StrFormat("{\"rank\": %d, \"generation\": %d, \"member\": %d, "
                                    "\"fitness\": %.17g, \"genes\": [%s],\n \"period_sweep\": %s}",
                                    e.rank(), e.individual().generation(),
                                    e.individual().member(),
                                    e.individual().evaluation().fitness(),
                                    absl::StrJoin(genes, ", "), sweep));
    if (n == 0) {
      const std::string csv = out_dir + "/" + id + "-best-trajectory.csv";
      std::string ignored;
      if (RunCapture({sim, "trajectory", "--genes", GenesArg(e.individual()), "--out", csv,
                      "--cycles", "3", "--rate", "100"},
                     &ignored) == 0)
        written->push_back(csv);
    }
    ++n;
  }
  std::string wave;
  if (int code = RunCapture({sim, "wave", "--periods", "0.2,2.0,19", "--cycles", "10"}, &wave);
      code != 0) {
    std::cerr << "gaitforge: gaitforge-sim wave failed (exit " << code << ")\n";
    return kFailed;
  }
  absl::StrAppend(&json, "],\n\"wave\": ", wave, "\n}\n");
  const std::string path = out_dir + "/" + id + "-report.json";
  std::ofstream(path) << json;
  written->push_back(path);
  std::string figures;
  if (RunPlotScript({"caterpillar", "--report", path, "--out-prefix", out_dir + "/" + id}) != 0) {
    std::cerr << "gaitforge: drawing the caterpillar figures failed\n";
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
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  auto hof = Hof(conn->study(), args[0], generation, g);
  if (!hof.ok()) return HofError(hof.status(), "trajectory " + args[0]);
  if (rank < 0 || rank >= hof->entries_size()) {
    std::cerr << "gaitforge: --rank = " << rank << " is out of range [0, "
              << hof->entries_size() - 1 << "]\n";
    return kNotFound;
  }
  std::string printed;
  code = RunCapture({SiblingBinary("gaitforge-sim"), "trajectory", "--genes",
                               GenesArg(hof->entries(rank).individual()), "--out", out, "--rate",
                               absl::StrFormat("%.17g", rate), "--cycles",
                               std::to_string(cycles)},
                              &printed);
  if (code != 0) return code == 2 ? kUsage : kFailed;
  std::cout << out << "\n";
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
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetStudyRequest req;
  req.set_study_id(args[0]);
  v1::StudySummary study;
  grpc::Status s = conn->study().GetStudy(&ctx, req, &study);
  if (!s.ok()) return ReportRpcError(s, "report " + args[0]);
  code = PlotStudy(conn->study(), args[0], out_dir, g, &written);
  const std::string& objective = study.spec().objective().name();
  if (code == kOk && objective == "caterpillar.calibration")
    code = CalibrationReport(*conn, study, out_dir, g, &written);
  else if (code == kOk && objective == "caterpillar.distance")
    code = CaterpillarReport(conn->study(), args[0], out_dir, g, 3, &written);
  for (const auto& f : written) std::cout << f << "\n";
  return code;
}

}  // namespace gaitforge::cli
