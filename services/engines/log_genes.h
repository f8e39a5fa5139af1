#pragma once
// Genes searched in log space: a parameter that spans decades (a contact's softness from
// 1e-6 to 1e-3, a creep from 1e-5 to 1) is searched by its logarithm, so that a step or a
// sample covers each decade alike instead of spending all but a sliver of the range on the
// top decade. LogGenesEngine wraps any engine made over the log-space bounds: the inner
// engine sees ln(x) for the marked genes, everything outside sees x. Pure, like the engines.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "services/engines/engine.h"

namespace gaitforge::engines {

class LogGenesEngine : public Engine {
 public:
  // `inner` searches the space whose gene i is ln(x) where log[i]; `natural` are the
  // bounds in the user's units (lo > 0 for every log gene; the mapped genes are clamped to
  // them, so that rounding in exp(ln(hi)) never leaves the range).
  LogGenesEngine(std::unique_ptr<Engine> inner, std::vector<bool> log, Bounds natural);

  int generation() const override { return inner_->generation(); }
  bool Done() const override { return inner_->Done(); }
  std::string StopReason() const override { return inner_->StopReason(); }
  const std::vector<Candidate>& Ask() const override { return asked_; }
  absl::Status Tell(const std::vector<Evaluation>& by_member) override;
  std::vector<Ranked> HallOfFame() const override;
  // The inner spread mapped to natural units at the best individual x: a log gene's
  // standard deviation s becomes x sinh(s), half the width of [x e^-s, x e^s].
  std::vector<double> Spread() const override;
  std::string SaveState() const override { return inner_->SaveState(); }
  absl::Status LoadState(std::string_view state) override;

 private:
  std::vector<double> Natural(std::vector<double> genes) const;
  void MapAsked();

  std::unique_ptr<Engine> inner_;
  std::vector<bool> log_;
  Bounds natural_;
  std::vector<Candidate> asked_;
};

// The log-space value of x for a log gene (x > 0), as the inner engine sees it.
double ToLogSpace(double x);

}  // namespace gaitforge::engines
