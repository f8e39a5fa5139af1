// The report of a robot.tracking study (`gaitforge report ID`; docs/objectives.md,
// "robot.tracking"): every path tracked by the study's robot with its descriptor's own
// parameters (the paper's gains) and with the study's best genes, under the study's
// options (plant, feed-forward), as per-tick CSVs, a JSON of their errors and a figure per
// path (gaitforge_plot.py tracking).
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"

namespace gaitforge::cli {
namespace {

std::string OptionOf(const v1::StudySpec& spec, const std::string& name) {
  const auto& o = spec.objective().options();
  const auto it = o.find(name);
  return it == o.end() ? "" : it->second;
}

// gaitforge-sim track on one path with the study's options and `set` on the plant; its JSON
// or "" (with a message).
std::string TrackPath(const v1::StudySpec& spec, const std::string& robot, const std::string& path,
                      const std::string& set, const std::string& ticks) {
  std::vector<std::string> argv = {SiblingBinary("gaitforge-sim"), "track", "--robot", robot,
                                   "--path", path, "--out", ticks};
  if (!set.empty()) argv.insert(argv.end(), {"--set", set});
  if (OptionOf(spec, "feedforward") == "model") {
    argv.insert(argv.end(), {"--feedforward", "model", "--model-set", OptionOf(spec, "model_set")});
    const auto& p = spec.objective().params();
    if (auto it = p.find("ff_iterations"); it != p.end())
      argv.insert(argv.end(), {"--ff-iterations", absl::StrFormat("%d", static_cast<int>(it->second))});
  }
  std::string out;
  if (RunCapture(argv, &out) != 0) {
    std::cerr << "gaitforge: gaitforge-sim track failed on " << path << "\n";
    return "";
  }
  return out;
}

}  // namespace

int TrackingReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                   const GlobalOptions& g, std::vector<std::string>* written) {
  const std::string& id = study.study_id();
  const v1::StudySpec& spec = study.spec();
  v1::GetHallOfFameResponse hof;
  if (int code = BestOfStudy(conn, id, g, &hof); code != kOk) return code;
  const auto& best = hof.entries(0).individual();
  const std::string dir = out_dir + "/" + id + "-tracking";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::string robot = spec.objective().robot();
  if (!spec.objective().robot_descriptor().empty()) {
    robot = dir + "/robot.yaml";
    std::ofstream(robot) << spec.objective().robot_descriptor();
  }
  const std::string plant = OptionOf(spec, "set");
  std::vector<std::string> genes;
  for (int i = 0; i < spec.bounds_size() && i < best.genes_size(); ++i)
    genes.push_back(absl::StrFormat("%s=%.17g", spec.bounds(i).name(), best.genes(i)));
  const std::string tuned = absl::StrJoin({plant, absl::StrJoin(genes, ",")}, plant.empty() ? "" : ",");
  std::string json = absl::StrCat("{\"study_id\": \"", id, "\", \"fitness\": ",
                                  absl::StrFormat("%.9g", best.evaluation().fitness()),
                                  ", \"best\": \"", absl::StrJoin(genes, ","), "\", \"paths\": [");
  for (int i = 0; i < spec.objective().recordings_size(); ++i) {
    const std::string path = DownloadRecording(conn, spec.objective().recordings(i), dir, g);
    if (path.empty()) return kFailed;
    const std::string own_csv = absl::StrCat(dir, "/path-", i, "-descriptor.csv");
    const std::string best_csv = absl::StrCat(dir, "/path-", i, "-best.csv");
    const std::string own = TrackPath(spec, robot, path, plant, own_csv);
    const std::string tuned_json = TrackPath(spec, robot, path, tuned, best_csv);
    if (own.empty() || tuned_json.empty()) return kFailed;
    absl::StrAppend(&json, i ? ", " : "", "{\"descriptor\": ", own, ", \"best\": ", tuned_json, "}");
    const std::string svg = absl::StrCat(out_dir, "/", id, "-tracking-", i, ".svg");
    if (RunPlotScript({"tracking", "--run", "the descriptor's parameters=" + own_csv, "--run",
                       "the study's best=" + best_csv, "--out", svg, "--title", id}) != 0) {
      std::cerr << "gaitforge: drawing the tracking figure failed\n";
      return kFailed;
    }
    written->push_back(svg);
  }
  const std::string report = out_dir + "/" + id + "-tracking.json";
  std::ofstream(report) << json << "]}\n";
  written->push_back(report);
  if (!g.json) std::cout << "best: " << absl::StrJoin(genes, ", ") << "\n";
  return kOk;
}

}  // namespace gaitforge::cli
