// `gaitforge diagnose plan SPEC --report FILE`: the recordings that would separate a
// diagnosis's leading explanations (docs/diagnosis.md, "Plan the experiment that decides").
// Reads the spec and the diagnosis's report, and runs gaitforge-sim plan (the workers' own
// model build) on the spec's recordings with the report's explanations; prints the plan in
// words (--json: its JSON) and writes the JSON to --output (default: plan.json beside the
// report).
#include <filesystem>
#include <fstream>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"
#include "services/core/file_text.h"
#include "services/diagnosis/fits.h"
#include "services/diagnosis/plan.h"
#include "services/diagnosis/plan_command.h"

namespace gaitforge::cli {
namespace {

namespace fs = std::filesystem;

// The spec's recordings as files (relative to the spec); empty, with a message, when one is
// a stored recording's hash rather than a file.
std::vector<std::string> RecordingFiles(const std::string& spec_path, const v1::DiagnosisSpec& d) {
  std::vector<std::string> files;
  auto add = [&](const std::string& r) {
    fs::path p(r);
    if (p.is_relative()) p = fs::path(spec_path).parent_path() / p;
    if (!fs::is_regular_file(p)) {
      std::cerr << "gaitforge: " << spec_path << ": recording '" << r
                << "' is not a file here; a plan simulates the recorded gaits and needs the "
                   "recordings as files\n";
      return false;
    }
    files.push_back(p.string());
    return true;
  };
  for (const auto& r : d.training())
    if (!add(r)) return {};
  for (const auto& r : d.held_out())
    if (!add(r)) return {};
  return files;
}

}  // namespace

int CmdDiagnosePlan(const GlobalOptions& g, const std::vector<std::string>& args,
                    const diagnosis::plan::Options& p, const std::string& output) {
  if (args.size() != 1 || p.report.empty()) {
    std::cerr << "gaitforge: usage: gaitforge diagnose plan SPEC.yaml --report "
                 "DIR/diagnosis.json [--propose N] [--random N] [--rivals N] [--seed N] "
                 "[--decisive X] [--output PLAN.json] [--json]\n";
    return kUsage;
  }
  v1::DiagnosisSpec d;
  if (int c = ReadDiagnosisSpec(args[0], &d); c) return c;
  const std::string report = core::ReadWholeFile(p.report).value_or("");
  if (report.empty()) {
    std::cerr << "gaitforge: --report: cannot read " << p.report
              << " (gaitforge diagnose writes it as --out/NAME-diagnosis/diagnosis.json)\n";
    return kNotFound;
  }
  auto model = diagnosis::plan::ReportModelOf(report, p.report);
  if (!model.ok()) {
    std::cerr << "gaitforge: " << model.status().message() << "\n";
    return kUsage;
  }
  const std::vector<std::string> recordings = RecordingFiles(args[0], d);
  if (recordings.empty()) return kUsage;
  // The robot as gaitforge-sim takes it: a built-in name, or the descriptor the spec
  // carries in a file (as the diagnosis's fits have it).
  const std::string robot = diagnosis::RobotArg(d);
  std::string json;
  const int code =
      RunCapture(diagnosis::PlanCommand(d, robot.empty() ? d.robot() : robot, recordings, p, *model), &json);
  if (code != 0) return code == 2 ? kUsage : code;
  const std::string out =
      output.empty() ? (fs::path(p.report).parent_path() / "plan.json").string() : output;
  std::ofstream(out) << json;
  if (g.json) {
    std::cout << json;
    return kOk;
  }
  auto words = diagnosis::plan::PlanWords(json, "gaitforge-sim plan");
  if (!words.ok()) {
    std::cerr << "gaitforge: " << words.status().message() << "\n";
    return 1;
  }
  std::cout << *words << "  written: " << out << "\n";
  return kOk;
}

}  // namespace gaitforge::cli
