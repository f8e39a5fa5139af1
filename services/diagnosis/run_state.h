// A diagnosis under way: what each stage of the pipeline (pipeline.h) leaves for the next
// and for the report (report.h).
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gaitforge/v1/diagnosis.pb.h"
#include "services/diagnosis/decision.h"
#include "services/diagnosis/fits.h"
#include "services/diagnosis/pipeline.h"
#include "services/diagnosis/range.h"
#include "services/diagnosis/studies.h"

namespace gaitforge::diagnosis {

struct RunState {
  RunState(const v1::DiagnosisSpec& spec, const Inputs& inputs, Studies& s, const Reporter& rep)
      : d(spec), in(inputs), studies(s), r(rep) {}
  v1::DiagnosisSpec d;  // a copy: the structure-first stage moves a structure into the base
  const Inputs& in;
  Studies& studies;
  const Reporter& r;

  int64_t n = 0;  // compared samples, for the BIC: period bins x channels per recording
  StudyInputs fit_inputs;
  std::vector<double> weights, train_floors;
  std::vector<double> variant_train;  // the uncalibrated model's mean training error per variant
  // Numerics first: the step the diagnosis started from (ms) and the uncalibrated model's
  // mean training error there (NAN: the stage did not run).
  double numerics_from_ms = NAN, numerics_from_error = NAN;
  // Resolution (structure: first): each count the diagnosis moved, from and to, with the
  // uncalibrated model's mean training error at both; empty: none moved.
  struct Refinement {
    std::string count;
    int from = 0, at = 0;
    double from_error = NAN, at_error = NAN;
  };
  std::vector<Refinement> resolution;
  int reused = 0;  // fits found in the database with the same spec, not run again

  Candidate base;
  // structure: first: the structural fit that became the baseline (its effects name it;
  // none: no structure was required), and the baseline's BIC before it.
  Candidate structure;
  double bic_before_structure = NAN;
  double floor_sd = 0;  // spread of the baseline's held-out error over the variants
  std::string located = "{}", located_held = "{}";
  std::vector<Candidate> screened, full;
  size_t singles = 0;  // full fits of single effects (the rest are pairs)

  DecisionRule rule;
  std::map<const Candidate*, FitRange> ranges;
  std::map<const Candidate*, RangeVerdict> judged;
  double tolerance = NAN;
  std::vector<int> set_aside, dropped;
  Decision decision;
  std::vector<const Candidate*> named;
  const Candidate* source = nullptr;  // the set-aside fit named[0] remains of
  std::string corrected;              // path of the corrected model, "" when none

  double Bic(const Candidate& c) const {
    return static_cast<double>(n) * std::log(std::max(c.train * c.train, 1e-300)) +
           c.k * std::log(static_cast<double>(n));
  }
};

// The report (report.cc): diagnosis.json with its figures drawn and listed.
std::string WriteReport(RunState& s);

}  // namespace gaitforge::diagnosis
