#pragma once
// `gaitforge diagnose plan` (docs/diagnosis.md, "Plan the experiment that decides"): which
// recordings would separate a diagnosis's leading explanations. The pure parts, without a
// simulator: the explanations a diagnosis report leaves, the candidate experiments a robot's
// gene space and the recorded gaits offer, and the greedy choice of the few that separate
// the most pairs of explanations. workers/tools/sim_plan.cc simulates them.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/core/flags.h"

namespace gaitforge::diagnosis::plan {

// What a plan is asked for: the same flags for gaitforge diagnose plan and gaitforge-sim plan.
struct Options {
  std::string report;  // the diagnosis's report (diagnosis.json)
  int propose = 3;     // recordings to propose
  int random = 12;     // random gaits among the candidates
  int rivals = 3;      // fitted explanations beside the baseline
  int64_t seed = 1;    // of the random gaits
  double decisive = 2;  // a pair parted by this many residuals is decided
  int max_shift = 10;  // time shifts (samples) a comparison may absorb, as the diagnosis's
  int threads = 1;     // simulations at once
};

// Registers --report, --propose, --random, --rivals, --seed, --decisive on `flags`, their
// help prefixed with `command` ("diagnose plan").
void AddFlags(core::Flags& flags, Options* o, const std::string& command);
// Each option within its range; the error names the flag.
absl::Status Check(const Options& o);
// The options as gaitforge-sim plan's arguments (--threads and --max-shift included).
std::vector<std::string> Arguments(const Options& o);

// One explanation of the recordings: the model with these parameter values (base
// parameters and the effect's; the nuisance ones left out, they belong to a recording).
struct Explanation {
  std::string id;  // "none" (the baseline) or the report's id, e.g. "ground.slope"
  std::vector<std::pair<std::string, double>> set;
  double train = 0;  // its training error, in the diagnosis's error
};

// What a report says of the model every explanation shares: the counts the diagnosis moved
// to (structure first) and the step it ran at when numerics first moved it.
struct ReportModel {
  std::vector<std::pair<std::string, int>> counts;
  double timestep_ms = 0;  // 0: the spec's or the robot's
};

// The baseline and up to `rivals` fitted explanations of a diagnosis report (its named
// effects first, then the runners-up that fitted better than the baseline on the training
// data, closest held out first; fits at a bound of their range and failed fits left out).
// An error naming `where` when the report is not JSON or leaves fewer than two.
absl::StatusOr<std::vector<Explanation>> ExplanationsFromReport(const std::string& json,
                                                                const std::string& where,
                                                                int rivals);
absl::StatusOr<ReportModel> ReportModelOf(const std::string& json, const std::string& where);

// A gait the diagnosis was given (a recording's command) and how many cycles it ran.
struct Recorded {
  std::string name;  // the recording's file name
  std::vector<double> genes;
  int cycles = 1;
};

// How a playback's recorded inputs are varied: every input times `scale`, time stretched by
// `time_scale`, and all inputs 0 from `release_at` of its (stretched) length on when
// release_at is in (0, 1): the robot let go, a passive decay.
struct InputVariant {
  double scale = 1, time_scale = 1, release_at = -1;
};

// A recording to propose: a gait (the controller's genes) run from rest for `cycles`, or
// (source >= 0) the inputs of recorded playback `source`, varied.
struct Experiment {
  std::string name;  // e.g. "train-1.csv, period x0.5" or "random 3"
  std::string kind;  // "recorded", "longer", "period", "random"; playbacks: "recorded",
                     // "scaled", "slower", "released"
  std::vector<double> genes;
  int cycles = 1;
  int source = -1;
  InputVariant inputs{};
};

// The candidates: each recorded gait as it was and run three times as long; with its period
// halved and doubled where the controller has a period gene T or a frequency gene f and the
// result stays in range; and `random` gaits drawn uniformly from the gene space (seeded),
// each as long as the longest recorded gait.
std::vector<Experiment> Candidates(const robots::RobotDescriptor& d,
                                   const std::vector<Recorded>& recorded, int random,
                                   uint64_t seed);

// The candidates of a robot driven by recorded inputs (playbacks; the arm): each recording's
// inputs as they were, at half and one and a half times their size, twice as slow, and let
// go half-way (a step held, then released: the decay shows stiffness and damping).
std::vector<Experiment> PlaybackCandidates(const std::vector<std::string>& names);

// Every unordered pair (i, j), i < j, of n explanations, in a fixed order.
std::vector<std::pair<int, int>> Pairs(int n);

// ratio[e][p]: how far candidate e separates pair p, in multiples of what the model leaves
// unexplained. Picks up to `count` candidates greedily, each the one that adds most to the
// pairs' best separations so far, counted up to `decisive` (a pair separated by `decisive`
// is decided; more does not help); stops when none adds. Ties go to the earlier candidate.
// A candidate whose ratios are not all finite (a simulation that failed) is never picked.
std::vector<int> Choose(const std::vector<std::vector<double>>& ratio, int count,
                        double decisive);

// Whether a diagnosis report leaves explanations its recordings could not tell apart: an
// ambiguous verdict, or none named while a fit without a parameter at a bound beat the
// baseline on the training data by the BIC margin. False for what is not a report.
bool Undecided(const std::string& report_json);

// Why a diagnosis plans by itself after its report (pipeline.cc, PlanStage):
//   kUndecided    Undecided(): the recordings could not tell explanations apart;
//   kUnexplained  none named, the report's unexplained_mismatch set, and a fit without a
//                 parameter at a bound fitted the training data better than the baseline
//                 (delta BIC < 0): the recording that would tell the nearest explanations
//                 apart, though none passed the rule;
//   kConfirm      an effect named: a plan is kept only when no recording given separates
//                 it from the baseline by the decisive level (RecordedSeparation), so the
//                 name rests on differences smaller than what the model gets wrong anyway.
enum class PlanReason { kNone, kUndecided, kUnexplained, kConfirm };
PlanReason WhyPlan(const std::string& report_json);
// The id of the report's first named effect ("" when none).
std::string FirstNamed(const std::string& report_json);

// In a plan's JSON, the best separation of the baseline ("none") from explanation `id` among
// the recordings it was given as they were (candidates of kind "recorded"), in multiples of
// the residual; NAN when the plan lacks either or is not JSON. `decisive`: the plan's level.
double RecordedSeparation(const std::string& plan_json, const std::string& id,
                          double* decisive = nullptr);

// A plan's JSON (gaitforge-sim plan) in words: the recordings to make, what each separates,
// and the pairs no candidate decides. An error when it is not a plan.
absl::StatusOr<std::string> PlanWords(const std::string& json, const std::string& where);

}  // namespace gaitforge::diagnosis::plan
