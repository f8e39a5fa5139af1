// The report of a calibration study (`gaitforge report ID` when the objective calibrates a
// robot): fitted parameters with their uncertainty (the final CMA-ES distribution),
// training and held-out error before (the robot's descriptor as it is) and after
// the fit, the real-to-simulated distance ratio per recording (paper 000 Fig. 9), and
// overlays of recorded and simulated markers (paper 000 Figs. 11, 12).
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"
#include "gaitforge/v1/recording.grpc.pb.h"

namespace gaitforge::cli {

int BestOfStudy(Connection& conn, const std::string& id, const GlobalOptions& g,
                v1::GetHallOfFameResponse* hof) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHallOfFameRequest hreq;
  hreq.set_study_id(id);
  grpc::Status s = conn.study().GetHallOfFame(&ctx, hreq, hof);
  if (!s.ok()) return ReportRpcError(s, "report " + id);
  if (hof->entries_size() == 0 || !hof->entries(0).individual().evaluation().valid()) {
    std::cerr << "gaitforge: report " << id << ": no valid result yet\n";
    return kFailed;
  }
  return kOk;
}

// Downloads a recording into dir; returns the CSV path ("" on failure, with a message).
std::string DownloadRecording(Connection& conn, const std::string& hash, const std::string& dir,
                              const GlobalOptions& g) {
  auto stub = v1::RecordingService::NewStub(conn.channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetRecordingRequest req;
  req.set_hash(hash);
  v1::GetRecordingResponse resp;
  grpc::Status s = stub->GetRecording(&ctx, req, &resp);
  if (!s.ok()) {
    std::cerr << "gaitforge: recording " << hash << ": " << s.error_message() << "\n";
    return "";
  }
  const std::string path = dir + "/" + hash.substr(0, 16) + "-" + resp.recording().name();
  std::ofstream(path, std::ios::binary) << resp.csv();
  std::ofstream(path + ".json", std::ios::binary) << resp.sidecar();
  return path;
}

namespace {

// Runs gaitforge-sim calibration-eval; returns its JSON or "".
std::string Evaluate(const std::vector<std::string>& files, const std::string& set,
                     const v1::StudySpec& spec, const std::string& out_dir) {
  if (files.empty()) return "{\"recordings\": []}";
  std::vector<std::string> argv = {SiblingBinary("gaitforge-sim"), "calibration-eval",
                                   "--recordings", absl::StrJoin(files, ",")};
  if (!set.empty()) argv.insert(argv.end(), {"--set", set});
  // A robot-agnostic calibration's robot: its descriptor as the study stored it (a robot
  // that is only files), else its built-in name.
  if (!spec.objective().robot_descriptor().empty()) {
    const std::string file = out_dir + "-robot.yaml";
    std::ofstream(file) << spec.objective().robot_descriptor();
    argv.insert(argv.end(), {"--robot", file});
  } else if (!spec.objective().robot().empty()) {
    argv.insert(argv.end(), {"--robot", spec.objective().robot()});
  }
  // Every option and param of the study's objective, so the report scores what the study did.
  std::vector<std::string> options, params;
  for (const auto& [k, v] : spec.objective().options()) options.push_back(k + "=" + v);
  for (const auto& [k, v] : spec.objective().params())
    params.push_back(absl::StrFormat("%s=%.17g", k, v));
  argv.insert(argv.end(), {"--options", absl::StrJoin(options, ";")});
  if (!params.empty())
    argv.insert(argv.end(), {"--objective-params", absl::StrJoin(params, ",")});
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  argv.insert(argv.end(), {"--out-dir", out_dir});
  std::string out;
  if (RunCapture(argv, &out) != 0) return "";
  return out;
}

}  // namespace

int CalibrationReport(Connection& conn, const v1::StudySummary& study, const std::string& out_dir,
                      const GlobalOptions& g, std::vector<std::string>* written) {
  const std::string& id = study.study_id();
  const v1::StudySpec& spec = study.spec();
  v1::GetHallOfFameResponse hof;
  if (int code = BestOfStudy(conn, id, g, &hof); code != kOk) return code;
  const auto& best = hof.entries(0).individual();
  std::vector<std::string> set;
  for (int i = 0; i < spec.bounds_size() && i < best.genes_size(); ++i)
    set.push_back(absl::StrFormat("%s=%.17g", spec.bounds(i).name(), best.genes(i)));

  const std::string dir = out_dir + "/" + id + "-calibration";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::vector<std::string> train, held;
  for (const auto& h : spec.objective().recordings()) {
    const std::string f = DownloadRecording(conn, h, dir, g);
    if (f.empty()) return kFailed;
    train.push_back(f);
  }
  for (const auto& h : spec.objective().held_out()) {
    const std::string f = DownloadRecording(conn, h, dir, g);
    if (f.empty()) return kFailed;
    held.push_back(f);
  }
  const std::string fitted = absl::StrJoin(set, ",");
  const std::string tb = Evaluate(train, "", spec, dir + "/train-before");
  const std::string ta = Evaluate(train, fitted, spec, dir + "/train-after");
  const std::string hb = Evaluate(held, "", spec, dir + "/held-before");
  const std::string ha = Evaluate(held, fitted, spec, dir + "/held-after");
  if (tb.empty() || ta.empty() || hb.empty() || ha.empty()) {
    std::cerr << "gaitforge: gaitforge-sim calibration-eval failed\n";
    return kFailed;
  }
  const auto channels = spec.objective().options().find("channels");
  std::string json = absl::StrCat(
      "{\"study_id\": \"", id, "\",\n\"channels\": ",
      JsonQuote(channels == spec.objective().options().end() ? "" : channels->second),
      ",\n\"fitness\": ",
                                  absl::StrFormat("%.9g", best.evaluation().fitness()),
                                  ",\n\"parameters\": [");
  for (int i = 0; i < spec.bounds_size() && i < best.genes_size(); ++i) {
    absl::StrAppend(&json, i ? ", " : "",
                    absl::StrFormat("{\"name\": \"%s\", \"value\": %.9g, \"spread\": %s, "
                                    "\"lo\": %.9g, \"hi\": %.9g}",
                                    spec.bounds(i).name(), best.genes(i),
                                    i < hof.spread_size() ? absl::StrFormat("%.9g", hof.spread(i))
                                                          : std::string("null"),
                                    spec.bounds(i).lo(), spec.bounds(i).hi()));
  }
  absl::StrAppend(&json, "],\n\"train_before\": ", tb, ",\n\"train_after\": ", ta,
                  ",\n\"held_out_before\": ", hb, ",\n\"held_out_after\": ", ha, "\n}\n");
  const std::string path = out_dir + "/" + id + "-calibration.json";
  std::ofstream(path) << json;
  written->push_back(path);
  if (RunPlotScript({"calibration", "--report", path, "--out-prefix", out_dir + "/" + id}) != 0) {
    std::cerr << "gaitforge: drawing the calibration figures failed\n";
    return kFailed;
  }
  // The distance ratio for recordings of a gait; the accelerations for error = acceleration.
  for (const char* f : {"-overlays.svg", "-errors.svg", "-distance-ratio.svg", "-accelerations.svg"})
    if (std::filesystem::exists(out_dir + "/" + id + f)) written->push_back(out_dir + "/" + id + f);
  if (!g.json) {
    std::cout << "fitted parameters (best of the study; +- the final search distribution's sd)\n";
    for (int i = 0; i < spec.bounds_size() && i < best.genes_size(); ++i)
      std::cout << absl::StrFormat("  %-32s %12.6g  +- %s\n", spec.bounds(i).name(), best.genes(i),
                                   i < hof.spread_size() ? absl::StrFormat("%.3g", hof.spread(i))
                                                         : std::string("n/a"));
  }
  return kOk;
}

}  // namespace gaitforge::cli
