#pragma once
// The ask/tell shape every optimiser has (after CMA-ES/libcmaes and pagmo2's bfe split):
// Ask() names the members of the current generation, the coordinator has them evaluated
// anywhere, Tell() takes the evaluations sorted by member and advances one generation.
// Engines are pure: no clocks, no threads, no I/O; randomness only from KeyedRng.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "services/core/byte_codec.h"

namespace gaitforge::engines {

// Fitness is "higher is better". Invalid evaluations rank below every valid one.
// `violation` is the total amount by which the study's constraints are violated (0 when
// feasible); see RanksBefore for how it ranks.
struct Evaluation {
  bool valid = false;
  double fitness = 0.0;
  std::string reason;
  double violation = 0.0;
  // A multi-objective engine's objectives (nsga2), each "higher is better", from the
  // metrics the study's spec names; empty for the single-objective engines.
  std::vector<double> objectives = {};
};

struct Candidate {
  int member = 0;
  std::vector<double> genes;
  // Set when the engine already knows this member's evaluation (a carried-over elite):
  // the coordinator does not evaluate it again.
  std::optional<Evaluation> known;
  // Where `genes` were first evaluated: for a carried member its original generation and
  // member index; otherwise the current generation and `member`.
  int origin_generation = 0;
  int origin_member = 0;
};

struct Ranked {
  int generation = 0;  // generation the individual was evaluated in
  int member = 0;      // its member index in that generation
  std::vector<double> genes;
  Evaluation eval;
};

struct Bounds {
  std::vector<double> lo;
  std::vector<double> hi;
  // Empty, or one per gene: true for a gene on a circle (lo and hi the same point).
  std::vector<bool> circular = {};
  size_t size() const { return lo.size(); }
  bool IsCircular(size_t i) const { return i < circular.size() && circular[i]; }
  // x brought into gene i's range: clamped to [lo, hi], or for a circular gene wrapped
  // into [lo, hi) (hi - lo is its period).
  double Fold(size_t i, double x) const;
  // x, or for a circular gene its representative nearest `ref` (x + whole periods), so
  // that differences and means across the seam are those on the circle.
  double Near(size_t i, double x, double ref) const;
};

// Bounds an engine can search: at least one gene, lo and hi finite with lo < hi. The
// message names the gene's index and its values.
absl::Status ValidateBounds(const Bounds& bounds);

// The same genotype: every gene equal within 1e-9 of its range, except that the circular
// genes may all be shifted by one common amount (a gait started at another phase).
bool SameGenotype(const std::vector<double>& a, const std::vector<double>& b,
                  const Bounds& bounds);

class Engine {
 public:
  virtual ~Engine() = default;

  // Index of the generation Ask() returns; equals the number of Tell() calls so far.
  virtual int generation() const = 0;
  virtual bool Done() const = 0;
  // Why the engine is Done(), in words for people ("" while it is not, or when it has no
  // reason of its own to stop: the GA runs until the spec's generations are done).
  virtual std::string StopReason() const { return ""; }
  // The members of the current generation; stable until the next Tell().
  virtual const std::vector<Candidate>& Ask() const = 0;
  // Evaluations of every member of the current generation, indexed by member. Checks all
  // inputs before changing any state.
  virtual absl::Status Tell(const std::vector<Evaluation>& by_member) = 0;
  // The best individuals seen, best first (the GA's elite of the last told generation).
  virtual std::vector<Ranked> HallOfFame() const = 0;
  // Per gene, the standard deviation of the engine's current search distribution in gene
  // units (CMA-ES: sigma * sqrt(C_ii) * range), an uncertainty for calibrations; empty when
  // the engine has no distribution (GA, sweep).
  virtual std::vector<double> Spread() const { return {}; }
  // Complete state; LoadState(SaveState()) continues bit-identically.
  virtual std::string SaveState() const = 0;
  virtual absl::Status LoadState(std::string_view state) = 0;
};

// Orders members for ranking (Deb's feasibility rule, then a total deterministic order):
// valid before invalid; feasible (violation 0) before infeasible; among feasible, higher
// fitness first; among infeasible, smaller violation first; then lower member index.
// Engines that need a scalar (roulette) treat infeasible members as weight 0.
bool RanksBefore(const Evaluation& a, int member_a, const Evaluation& b, int member_b);

// One evaluation in engine state (every engine's state uses this encoding).
void WriteEvaluation(core::ByteWriter& w, const Evaluation& e);
Evaluation ReadEvaluation(core::ByteReader& r);

// A list of ranked individuals (a hall of fame, the sweep's grid leaders) in engine state:
// count, then generation, member, genes and evaluation of each. ReadRanked returns false
// when the count exceeds `cap` or any genes vector is not `n` long (the reader's own errors
// show in r.status()).
void WriteRanked(core::ByteWriter& w, const std::vector<Ranked>& v);
bool ReadRanked(core::ByteReader& r, std::vector<Ranked>& v, size_t cap, size_t n);

}  // namespace gaitforge::engines
