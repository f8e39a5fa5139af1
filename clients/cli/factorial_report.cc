// A factorial sweep's statistics (sweep.factors; docs/engines.md, "Factorial designs"): the
// design and every member as JSON, then clients/python/gaitforge_factorial.py (scipy's
// Welch test, statsmodels' two-way ANOVA, matplotlib's box plot).
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "clients/cli/cli.h"
#include "services/core/subprocess.h"
#include "services/spec/engine_kinds.h"

namespace gaitforge::cli {
namespace {

// The response: the metric the objective's fitness option names, else the fitness.
std::string Response(const v1::StudySpec& spec) {
  const auto& options = spec.objective().options();
  if (auto it = options.find("fitness"); it != options.end() && it->second != "travel")
    return it->second;
  return "fitness";
}

void WriteDesign(const v1::StudySpec& spec, std::ostream& out) {
  out << "{\"factors\": [";
  for (int f = 0; f < spec.sweep().factors_size(); ++f) {
    const v1::SweepFactor& factor = spec.sweep().factors(f);
    const int levels = factor.genes_size() > 0 ? factor.genes(0).values_size() : 0;
    const std::string name = factor.name().empty() ? absl::StrCat("factor", f + 1) : factor.name();
    out << (f ? ", " : "") << "{\"name\": \"" << name << "\", \"levels\": [";
    for (int l = 0; l < levels; ++l)
      out << (l ? ", " : "") << "\""
          << (factor.levels_size() == levels ? factor.levels(l) : absl::StrCat(l + 1)) << "\"";
    out << "], \"genes\": [";
    for (int k = 0; k < factor.genes_size(); ++k)
      out << (k ? ", " : "") << spec::GeneIndex(spec, factor.genes(k).gene());
    out << "], \"values\": [";
    for (int k = 0; k < factor.genes_size(); ++k) {
      out << (k ? ", " : "") << "[";
      for (int l = 0; l < factor.genes(k).values_size(); ++l)
        out << (l ? ", " : "") << absl::StrFormat("%.17g", factor.genes(k).values(l));
      out << "]";
    }
    out << "]}";
  }
  out << "], \"members\": ";
}

}  // namespace

int PlotFactorial(v1::StudyService::Stub& stub, const v1::StudySummary& study,
                  const std::string& out_dir, const GlobalOptions& g,
                  std::vector<std::string>* written) {
  const v1::StudySpec& spec = study.spec();
  if (spec.sweep().factors_size() < 2) return kOk;
  const std::string prefix = out_dir + "/" + study.study_id() + "-factorial";
  std::ostringstream data;
  WriteDesign(spec, data);
  if (!WriteMembersJson(stub, study, g, data)) {
    std::cerr << "gaitforge: the factorial statistics could not list the study's members\n";
    return kFailed;
  }
  data << "}\n";
  std::ofstream(prefix + "-data.json") << data.str();
  const std::vector<std::string> argv = {
      core::Python(), core::PythonScript("gaitforge_factorial.py"),
      "--data",       prefix + "-data.json",
      "--metric",     Response(spec),
      "--out-prefix", prefix,
      "--title",      study.study_id()};
  std::string ignored;
  if (core::RunCapture(argv, &ignored) != 0) {
    std::cerr << "gaitforge: the factorial statistics failed (needs " << core::Python()
              << " with python3-scipy, python3-statsmodels and python3-matplotlib)\n";
    return kFailed;
  }
  std::ifstream summary(prefix + ".txt");
  std::cerr << summary.rdbuf();
  for (const char* ext : {".json", ".txt", ".svg"}) written->push_back(prefix + ext);
  return kOk;
}

}  // namespace gaitforge::cli
