// Locating the mismatch: see diagnosis_locate.h.
#include "clients/cli/diagnosis_locate.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"

namespace gaitforge::cli::diagnosis {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str().empty() ? "{}" : text.str();
}

}  // namespace

std::string Locate(const Candidate& c, const std::vector<std::string>& files,
                   const v1::DiagnosisSpec& d, const std::string& dir, const std::string& stem,
                   const std::string& out_json, const std::string& figure) {
  (void)HeldOutError(c, files, d, dir + "/" + stem);
  std::vector<std::string> argv = {
      "/usr/bin/python3",
      std::filesystem::path(PlotScriptPath()).parent_path().string() + "/gaitforge_locate.py",
      "--eval", dir + "/" + stem + "/eval.json", "--out", dir + "/" + out_json};
  if (!figure.empty()) argv.insert(argv.end(), {"--figure", dir + "/" + figure});
  // The model's own spread on the same recordings: the fit under the other numeric
  // variants. A drift or shape the variants already disagree on is chaos, not a mismatch.
  const std::vector<std::string> spread = VariantEvals(c, files, d, dir, stem);
  std::string ignored;
  if (!spread.empty()) {
    std::vector<std::string> with = argv;
    with.insert(with.end(), {"--variants", absl::StrJoin(spread, ",")});
    if (RunCapture(with, &ignored) == 0) return ReadAll(dir + "/" + out_json);
    // e.g. a variant's simulation invalid on one recording: locate against noise alone.
    std::cerr << "gaitforge: warning: locating against the numeric variants failed on " << dir
              << "/" << stem << "; locating against the noise alone\n";
  }
  if (const int code = RunCapture(argv, &ignored); code != 0) {
    std::cerr << "gaitforge: warning: locating the mismatch failed (gaitforge_locate.py exit "
              << code << " on " << dir << "/" << stem << "/eval.json); the report has no "
              << "'where it showed' for those recordings\n";
    return "{}";
  }
  return ReadAll(dir + "/" + out_json);
}

}  // namespace gaitforge::cli::diagnosis
