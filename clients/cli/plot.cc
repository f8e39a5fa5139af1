// `gaitforge plot ID`: figures of a study as image files, drawn by matplotlib through
// clients/python/gaitforge_plot.py.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/strings/str_format.h"
#include "clients/cli/cli.h"
#include "services/core/subprocess.h"

namespace gaitforge::cli {
namespace {

std::string PlotScript() {
  if (const char* s = std::getenv("GAITFORGE_PLOT_SCRIPT")) return s;
  return core::PythonScript("gaitforge_plot.py");
}

using core::Python;

// A sweep study's members as JSON for the script's sweep figure: the gene names, bounds and
// grid points per gene, and every member as [generation, fitness or null, violation, genes...].
bool WriteSweepData(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                    const GlobalOptions& g, const std::string& path) {
  const v1::StudySpec& spec = study.spec();
  std::ofstream out(path);
  out << "{\"genes\": [";
  for (int i = 0; i < spec.bounds_size(); ++i)
    out << (i ? ", " : "") << "[\"" << spec.bounds(i).name() << "\", " << spec.bounds(i).lo()
        << ", " << spec.bounds(i).hi() << ", "
        << spec.sweep().points_per_axis(spec.sweep().points_per_axis_size() == 1 ? 0 : i) << "]";
  out << "], \"members\": [";
  bool first = true;
  const bool listed = ForEachMember(stub, study, g, [&](int gen, const v1::Individual& m) {
    out << (first ? "" : ", ") << "[" << gen << ", ";
    first = false;
    if (m.evaluation().valid())
      out << absl::StrFormat("%.17g", m.evaluation().fitness());
    else
      out << "null";
    out << ", " << absl::StrFormat("%.17g", m.violation());
    for (double x : m.genes()) out << ", " << absl::StrFormat("%.17g", x);
    out << "]";
  });
  out << "]}\n";
  return listed && static_cast<bool>(out);
}

// A sweep study's heat map of its grid and its Nelder-Mead searches' path (paper 001's
// figures): ID-sweep.svg beside the fitness curve; a factorial design's statistics
// (PlotFactorial). Nothing for another engine.
int PlotSweep(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
              const GlobalOptions& g, std::vector<std::string>* written) {
  v1::StudySummary study;
  if (grpc::Status s = FetchStudy(stub, g, id, &study); !s.ok())
    return ReportRpcError(s, "plot " + id);
  if (study.spec().engine() != "sweep" || study.spec().bounds_size() < 1) return kOk;
  // A factorial design is no grid over genes: its statistics and box plot instead.
  if (study.spec().sweep().factors_size() > 0)
    return PlotFactorial(stub, study, out_dir, g, written);
  const std::string json = out_dir + "/" + id + "-sweep.json";
  const std::string svg = out_dir + "/" + id + "-sweep.svg";
  if (!WriteSweepData(stub, study, g, json) ||
      RunPlotScript({"sweep", "--data", json, "--out", svg, "--title", id}) != 0) {
    std::cerr << "gaitforge: the sweep figure failed (needs " << Python()
              << " with python3-matplotlib)\n";
    return kFailed;
  }
  written->push_back(svg);
  return kOk;
}

}  // namespace

std::string PlotScriptPath() { return PlotScript(); }

bool ForEachMember(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                   const GlobalOptions& g,
                   const std::function<void(int, const v1::Individual&)>& fn) {
  for (int gen = 0; gen < study.generations_done(); ++gen) {
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    v1::ListIndividualsRequest req;
    req.set_study_id(study.study_id());
    req.set_generation(gen);
    v1::ListIndividualsResponse resp;
    if (!stub.ListIndividuals(&ctx, req, &resp).ok()) return false;
    for (const auto& m : resp.individuals())
      if (!m.carried()) fn(gen, m);
  }
  return true;
}

bool WriteMembersJson(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                      const GlobalOptions& g, std::ostream& out) {
  bool first = true;
  out << "[";
  const bool listed = ForEachMember(stub, study, g, [&](int gen, const v1::Individual& m) {
    out << (first ? "" : ", ") << "{\"generation\": " << gen << ", \"member\": " << m.member()
        << ", \"genes\": [";
    first = false;
    for (int i = 0; i < m.genes_size(); ++i)
      out << (i ? ", " : "") << absl::StrFormat("%.17g", m.genes(i));
    out << "], \"valid\": " << (m.evaluation().valid() ? "true" : "false")
        << ", \"fitness\": " << absl::StrFormat("%.17g", m.evaluation().fitness())
        << ", \"violation\": " << absl::StrFormat("%.17g", m.violation()) << ", \"metrics\": {";
    bool first_metric = true;
    for (const auto& [name, v] : m.evaluation().metrics()) {
      if (!std::isfinite(v)) continue;
      out << (first_metric ? "" : ", ") << "\"" << name << "\": " << absl::StrFormat("%.17g", v);
      first_metric = false;
    }
    out << "}}";
  });
  out << "]";
  return listed;
}

int RunPlotScript(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {Python(), PlotScript()};
  argv.insert(argv.end(), args.begin(), args.end());
  pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> a;
    for (auto& s : argv) a.push_back(s.data());
    a.push_back(nullptr);
    if (int devnull = open("/dev/null", O_WRONLY); devnull >= 0) dup2(devnull, STDOUT_FILENO);
    execv(a[0], a.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

int PlotStudy(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
              const GlobalOptions& g, std::vector<std::string>* written) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHistoryRequest req;
  req.set_study_id(id);
  v1::GetHistoryResponse resp;
  grpc::Status s = stub.GetHistory(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "plot " + id);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string json = out_dir + "/" + id + "-history.json";
  std::ofstream(json) << ToJson(resp) << "\n";
  const std::string svg = out_dir + "/" + id + "-fitness.svg";
  if (RunPlotScript({"fitness", "--history", json, "--out", svg, "--title", id}) != 0) {
    std::cerr << "gaitforge: plotting failed (needs " << Python()
              << " with python3-matplotlib; script " << PlotScript() << ")\n";
    return kFailed;
  }
  written->push_back(svg);
  if (int code = PlotPareto(stub, id, out_dir, g, written); code != kOk) return code;
  return PlotSweep(stub, id, out_dir, g, written);
}

int CmdPlot(const GlobalOptions& g, const std::vector<std::string>& args,
            const std::string& out_dir) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge plot STUDY_ID [--out DIR]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  std::vector<std::string> written;
  code = PlotStudy(conn->study(), args[0], out_dir, g, &written);
  for (const auto& f : written) std::cout << f << "\n";
  return code;
}

}  // namespace gaitforge::cli
