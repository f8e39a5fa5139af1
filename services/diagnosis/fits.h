// The gap finder's fits: each candidate explanation (the base model plus effects) as a
// calibration study on the coordinator, and its errors on recordings scored locally with
// `gaitforge-sim calibration-eval` under numerically irrelevant variants of the model.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/diagnosis/decision.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "gaitforge/v1/study.pb.h"

namespace gaitforge::diagnosis {

// A fitted explanation: its FitScore (effects, ok, bic, held, held_variants) and the study.
struct Candidate : FitScore {
  std::string label;                  // effect id(s), "baseline" for none
  std::vector<v1::GeneBound> genes;   // what the study fits
  std::vector<double> mean0;          // where the fit starts (Make: as `nominal`)
  std::vector<double> nominal;        // per gene, its value with its effect absent (Make)
  double sigma0 = 0.25;               // its first step, a share of each gene's range
  std::vector<std::string> gene_effect;  // per gene, the effect id it belongs to ("": none)
  std::string study_id;
  std::string reason;
  std::vector<double> values, spread;
  std::vector<std::string> bound_params;  // effect parameters at the edge of their range
  int k = 0;                          // fitted parameters (nuisances included)
};

// Numerically irrelevant variants of the model ("" is the model as fitted): other
// timesteps and contact softnesses, those of them whose parameter d's robot has.
std::vector<std::string> NumericVariants(const v1::DiagnosisSpec& d);

// The index of the variant with the smallest timestep among `variants` (NumericVariants'
// "simulation.timestep_s=H" entries), -1 when none has one. The model's own step ("") is
// coarser than the finest variant by construction (the variants halve it).
int FinestStepVariant(const std::vector<std::string>& variants);

// d's robot: a built-in robot, or the descriptor the spec carries.
absl::StatusOr<std::shared_ptr<const robots::RobotDescriptor>> RobotOf(const v1::DiagnosisSpec& d);

// gaitforge-sim's --robot for d's robot: a file holding the descriptor the spec carries (in
// the temporary directory, named by the content's hash), a built-in generic robot's name,
// or "" for a built-in robot with a model kind of its own (gaitforge-sim's default model).
std::string RobotArg(const v1::DiagnosisSpec& d);

// The candidate with these effects: its genes (base parameters, effect parameters, time
// offset), start point and parameter count.
Candidate Make(const v1::DiagnosisSpec& d, const std::vector<std::string>& effect_ids);

// Starts c where fit `from` ended: each gene `from` also fits at its fitted value (clamped
// to c's range), with a first step of 0.05 of each range; with `hold`, c's ranges shrink to
// within 2% of those values and the first step is 0.1 (a screening fit on a fitted model).
void StartAt(const Candidate& from, Candidate* c, bool hold);

// Starts `pair` (a candidate with the effects of single fits a and b) where the better of
// the two (the lower training error among those ok) ended: its base parameters and its
// effect's, the other effect at its nominal value (absent), with a first step of 0.1 of
// each range; so the pair begins at least as good as its better member and its budget
// goes to what the second effect adds. False (pair unchanged) when neither fit is ok.
bool StartAtBetter(const Candidate& a, const Candidate& b, Candidate* pair);

// d with c's effects moved into the base model: their parameters become base
// parameters over their ranges (fitted in every later study), and they leave the candidates.
v1::DiagnosisSpec WithStructure(const v1::DiagnosisSpec& d, const Candidate& c);

// What every fit's study names: the recordings (content hashes) and the training weights.
struct StudyInputs {
  std::vector<std::string> train, held;
  std::string weights;  // the calibration objective's `weights` option; "" weighs alike
};

// The calibration objective of d's robot: the catalog's objective that calibrates it, or
// robot.calibration for a robot on the generic builder. Empty when the robot has none
// (Validate refuses such a spec).
std::string CalibrationObjective(const v1::DiagnosisSpec& d);

// The calibration study that fits c.
v1::StudySpec StudyFor(const v1::DiagnosisSpec& d, const Candidate& c, int evaluations,
                       const StudyInputs& in);

// Error of calibration-eval on each file with c's fit (+ extra_set); empty on failure.
// With out_dir, the simulated markers and eval.json are written there.
std::vector<double> FileErrors(const Candidate& c, const std::vector<std::string>& files,
                               const v1::DiagnosisSpec& d, const std::string& out_dir,
                               const std::string& extra_set = "");
// Their mean; NAN on failure.
double HeldOutError(const Candidate& c, const std::vector<std::string>& files,
                    const v1::DiagnosisSpec& d, const std::string& out_dir,
                    const std::string& extra_set = "");

// Where variant i's evaluation under prefix is written: prefix itself for the first (the
// model as fitted), prefix-variant-i for the others.
std::string VariantDir(const std::string& prefix, size_t i);
// c's mean error on files under every numeric variant, two at a time (NAN where one fails);
// with a prefix, each evaluation (eval.json, simulated markers) goes to VariantDir(prefix, i).
std::vector<double> VariantErrors(const Candidate& c, const std::vector<std::string>& files,
                                  const v1::DiagnosisSpec& d, const std::string& prefix = "");

// Whether d's weighting measures each training file's floor over the numeric variants
// (floor, pooled): the later stages that read the variants' errors need it.
bool FloorsMeasured(const v1::DiagnosisSpec& d);

// Training weights from the files' floors (sds), summing to the file count.
// pooled false (weighting: floor): 1 / sd^2, with sd at least a tenth of the median.
// pooled true (weighting: pooled): 1 / (sd^2 + m^2), m the median sd: a file's own numeric
// spread plus the typical one (before normalising no weight exceeds 1 / m^2), so that a file
// the model's numerics barely move cannot carry the fit alone, while a chaotic one still
// counts less.
std::vector<double> WeightsFromFloors(const std::vector<double>& floors, bool pooled);

// weighting: floor or pooled: the training files' weights (WeightsFromFloors) from the sd of
// the uncalibrated model's error over the variants (floors: the sds). Empty when an
// evaluation fails. variant_means (optional): per numeric variant, the uncalibrated model's
// mean error over the files.
std::vector<double> FloorWeights(const v1::DiagnosisSpec& d, const std::vector<std::string>& files,
                                 std::vector<double>* floors,
                                 std::vector<double>* variant_means = nullptr);

// A caution when the model's own numerics are not converged for these recordings: some
// numeric variant (variants[i], "" the model as it is) of the uncalibrated model misses the
// training recordings by less than kUnconvergedShare of the model's own error; "" otherwise.
inline constexpr double kUnconvergedShare = 0.8;
// The robot parameter that holds the model's step (the numeric variants change it).
inline constexpr char kTimestepParam[] = "simulation.timestep_s";
// The robot parameters every evaluation of the diagnosis sets before `extra_set` (a
// variant's): its own step when the spec gives one (timestep_ms), unless extra_set sets it.
std::string BaseSet(const v1::DiagnosisSpec& d, const std::string& extra_set);
// Numerics first: the timestep variant finer than the model's own step that brings the
// uncalibrated model closest to the training recordings, if it does by more than
// 1 - kUnconvergedShare of the model's own error; -1 otherwise. Its step in ms.
double FinerStepMs(const std::vector<std::string>& variants,
                   const std::vector<double>& training_errors, double own_step_ms);
std::string NumericsNote(const std::vector<std::string>& variants,
                         const std::vector<double>& training_errors,
                         const DecisionRule& unit = DecisionRule());

// run(0) .. run(n - 1), two at a time (each typically one gaitforge-sim process).
void TwoAtATime(size_t n, const std::function<void(size_t)>& run);

// c's held-out error under every variant, and their mean (NAN if any variant fails).
// With a prefix, the evaluations are kept (VariantErrors).
void ScoreHeldOut(Candidate& c, const std::vector<std::string>& files, const v1::DiagnosisSpec& d,
                  const std::string& prefix = "");

}  // namespace gaitforge::diagnosis
