#pragma once
// The best individuals an engine has seen across all its generations, best first, for
// engines whose members do not carry over (CMA-ES, the sweep). Order: RanksBefore
// (Deb's feasibility rule) on the evaluations, then the earlier (generation, member).
// Entries are distinct genotypes (SameGenotype: equal up to one shift of the circular
// genes); of two that are the same, the hall keeps the better.
#include <vector>

#include "services/engines/engine.h"

namespace gaitforge::engines {

class HallOfFame {
 public:
  explicit HallOfFame(int capacity = 10, Bounds bounds = {})
      : capacity_(capacity), bounds_(std::move(bounds)) {}

  // True when an individual with `eval` would enter the hall now (cheap pre-check, so
  // callers copy genes only for those that do).
  bool Admits(const Evaluation& eval) const;
  // Inserts one individual; keeps at most `capacity` best.
  void Offer(int generation, int member, const std::vector<double>& genes,
             const Evaluation& eval);

  const std::vector<Ranked>& entries() const { return entries_; }
  void set_entries(std::vector<Ranked> entries) { entries_ = std::move(entries); }
  int capacity() const { return capacity_; }

 private:
  int capacity_;
  Bounds bounds_;
  std::vector<Ranked> entries_;
};

// Strict "a is better than b" on evaluations alone: RanksBefore without the member tie-break.
inline bool Better(const Evaluation& a, const Evaluation& b) {
  return RanksBefore(a, 0, b, 0);
}

}  // namespace gaitforge::engines
