// A multi-objective study's Pareto figure (engine nsga2; docs/engines.md, "NSGA-II"): its
// objectives, the final front (the hall of fame) and every member as JSON, then
// clients/python/gaitforge_plot.py's `pareto` figure.
#include <fstream>
#include <iostream>
#include <sstream>

#include "clients/cli/cli.h"
#include "services/core/subprocess.h"

namespace gaitforge::cli {

int PlotPareto(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
               const GlobalOptions& g, std::vector<std::string>* written) {
  v1::StudySummary study;
  if (grpc::Status s = FetchStudy(stub, g, id, &study); !s.ok())
    return ReportRpcError(s, "plot " + id);
  const v1::Nsga2Spec& spec = study.spec().nsga2();
  if (spec.objectives_size() < 2 || study.generations_done() < 1) return kOk;
  auto hof = Hof(stub, id, -1, g);
  if (!hof.ok()) {
    std::cerr << "gaitforge: plot " << id << ": " << hof.status().message() << "\n";
    return kFailed;
  }
  std::ostringstream data;
  data << "{\"objectives\": [";
  for (int i = 0; i < spec.objectives_size(); ++i)
    data << (i ? ", " : "") << "{\"metric\": \"" << spec.objectives(i).metric()
         << "\", \"sense\": \"" << spec.objectives(i).sense() << "\"}";
  data << "], \"front\": [";
  for (int i = 0; i < hof->entries_size(); ++i)
    data << (i ? ", " : "") << "[" << hof->entries(i).individual().generation() << ", "
         << hof->entries(i).individual().member() << "]";
  data << "], \"members\": ";
  if (!WriteMembersJson(stub, study, g, data)) {
    std::cerr << "gaitforge: the Pareto figure could not list the study's members\n";
    return kFailed;
  }
  data << "}\n";
  const std::string json = out_dir + "/" + id + "-pareto.json";
  const std::string svg = out_dir + "/" + id + "-pareto.svg";
  std::ofstream(json) << data.str();
  if (RunPlotScript({"pareto", "--data", json, "--out", svg, "--title", id}) != 0) {
    std::cerr << "gaitforge: the Pareto figure failed (needs " << core::Python()
              << " with python3-matplotlib)\n";
    return kFailed;
  }
  written->push_back(json);
  written->push_back(svg);
  return kOk;
}

}  // namespace gaitforge::cli
