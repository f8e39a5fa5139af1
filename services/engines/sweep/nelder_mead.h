#pragma once
// One Nelder-Mead search in batch form: it names the points it needs evaluated next
// (pending()), all of which can be evaluated in parallel, and advances when told their
// evaluations. Method and coefficients after Lagarias, Reeds, Wright & Wright, "Convergence
// properties of the Nelder-Mead simplex method in low dimensions", SIAM J. Optim. 9(1),
// 1998: reflection 1, expansion 2, contraction 1/2, shrink 1/2. Batches: the n new vertices
// of the initial simplex at once; then one reflection point; then, as needed, one
// expansion or contraction point; a shrink's n points at once.
// Vertices are compared by Deb's rule (engines::Better), so infeasible and invalid
// points are "worse" than feasible ones. Points are clamped into the box.
#include <optional>
#include <vector>

#include "services/core/byte_codec.h"
#include "services/engines/engine.h"

namespace gaitforge::engines::sweep {

class NelderMead {
 public:
  // x0 (already evaluated as f0) is the first vertex; vertex i = x0 + step_i e_i, or
  // x0 - step_i e_i when that leaves the box.
  NelderMead(const std::vector<double>& x0, const Evaluation& f0,
             const std::vector<double>& steps, const Bounds& bounds);

  const std::vector<std::vector<double>>& pending() const { return pending_; }
  // Evaluations of pending(), in order. Then either new points are pending or done().
  // `tolerance` is relative to each gene's range.
  void Tell(const std::vector<Evaluation>& evals, const Bounds& bounds, int max_iterations,
            double tolerance);
  bool done() const { return phase_ == Phase::kDone; }
  int iterations() const { return iterations_; }
  const std::vector<double>& best() const { return x_[0]; }
  const Evaluation& best_eval() const { return f_[0]; }

  void Save(core::ByteWriter& w) const;
  // Reads what Save wrote; nullopt when malformed (n genes expected).
  static std::optional<NelderMead> Load(core::ByteReader& r, size_t n);

 private:
  enum class Phase { kInit, kReflect, kExpand, kContractOut, kContractIn, kShrink, kDone };
  NelderMead() = default;
  void BeginIteration(const Bounds& bounds, int max_iterations, double tolerance);
  void ReplaceWorst(const std::vector<double>& x, const Evaluation& f);
  void Shrink(const Bounds& bounds);
  // c + t (p - c), clamped into the box.
  std::vector<double> Along(const std::vector<double>& p, double t, const Bounds& b) const;

  Phase phase_ = Phase::kInit;
  std::vector<std::vector<double>> x_;  // n + 1 vertices, best first after sorting
  std::vector<Evaluation> f_;
  std::vector<double> centroid_;        // of the best n vertices, this iteration
  std::vector<double> xr_;              // the reflection point and its evaluation
  Evaluation fr_;
  int iterations_ = 0;
  std::vector<std::vector<double>> pending_;
};

}  // namespace gaitforge::engines::sweep
