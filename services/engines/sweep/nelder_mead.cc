#include "services/engines/sweep/nelder_mead.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "services/engines/hall_of_fame.h"

namespace gaitforge::engines::sweep {
namespace {

constexpr double kReflect = 1.0, kExpand = 2.0, kContract = 0.5, kShrink = 0.5;


}  // namespace

NelderMead::NelderMead(const std::vector<double>& x0, const Evaluation& f0,
                       const std::vector<double>& steps, const Bounds& bounds) {
  const size_t n = x0.size();
  x_.assign(1, x0);
  f_.assign(1, f0);
  for (size_t i = 0; i < n; ++i) {
    std::vector<double> v = x0;
    v[i] = x0[i] + steps[i] <= bounds.hi[i] || bounds.IsCircular(i) ? x0[i] + steps[i]
                                                                    : x0[i] - steps[i];
    v[i] = bounds.Fold(i, v[i]);
    pending_.push_back(std::move(v));
  }
}

std::vector<double> NelderMead::Along(const std::vector<double>& p, double t,
                                      const Bounds& b) const {
  std::vector<double> out(p.size());
  for (size_t i = 0; i < p.size(); ++i)
    out[i] = b.Fold(i, centroid_[i] + t * (b.Near(i, p[i], centroid_[i]) - centroid_[i]));
  return out;
}

void NelderMead::ReplaceWorst(const std::vector<double>& x, const Evaluation& f) {
  x_.back() = x;
  f_.back() = f;
}

void NelderMead::Shrink(const Bounds& b) {
  // Every vertex but the best moves halfway towards it; n points evaluated at once.
  pending_.clear();
  for (size_t v = 1; v < x_.size(); ++v) {
    std::vector<double> p(x_[v].size());
    for (size_t i = 0; i < p.size(); ++i)
      p[i] = b.Fold(i, x_[0][i] + kShrink * (x_[v][i] - x_[0][i]));
    pending_.push_back(std::move(p));
  }
  phase_ = Phase::kShrink;
}

void NelderMead::BeginIteration(const Bounds& b, int max_iterations, double tolerance) {
  // Order the vertices best first (stable: among equals the older vertex stays ahead).
  std::vector<size_t> order(x_.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t c) { return Better(f_[a], f_[c]); });
  std::vector<std::vector<double>> x;
  std::vector<Evaluation> f;
  for (size_t k : order) {
    x.push_back(std::move(x_[k]));
    f.push_back(std::move(f_[k]));
  }
  x_ = std::move(x);
  f_ = std::move(f);
  // Circular genes in the best vertex's chart: every vertex's representative nearest it.
  for (size_t v = 1; v < x_.size(); ++v)
    for (size_t i = 0; i < x_[v].size(); ++i) x_[v][i] = b.Near(i, x_[v][i], x_[0][i]);
  pending_.clear();
  // Converged when every vertex is within `tolerance` (fraction of the range) of the best.
  double diameter = 0;
  for (size_t v = 1; v < x_.size(); ++v)
    for (size_t i = 0; i < x_[v].size(); ++i)
      diameter = std::max(diameter, std::abs(x_[v][i] - x_[0][i]) / (b.hi[i] - b.lo[i]));
  if (iterations_ >= max_iterations || diameter <= tolerance) {
    phase_ = Phase::kDone;
    return;
  }
  const size_t n = x_.size() - 1;
  centroid_.assign(x_[0].size(), 0.0);
  for (size_t v = 0; v < n; ++v)
    for (size_t i = 0; i < centroid_.size(); ++i) centroid_[i] += x_[v][i] / n;
  xr_ = Along(x_[n], -kReflect, b);  // c + (c - x_worst)
  pending_.push_back(xr_);
  phase_ = Phase::kReflect;
}

void NelderMead::Tell(const std::vector<Evaluation>& evals, const Bounds& b,
                      int max_iterations, double tolerance) {
  const size_t n = x_[0].size();
  switch (phase_) {
    case Phase::kInit:
      for (size_t k = 0; k < pending_.size(); ++k) {
        x_.push_back(pending_[k]);
        f_.push_back(evals[k]);
      }
      BeginIteration(b, max_iterations, tolerance);
      return;
    case Phase::kReflect:
      fr_ = evals[0];
      if (Better(fr_, f_[0])) {  // better than the best: try going further
        pending_ = {Along(xr_, kExpand, b)};
        phase_ = Phase::kExpand;
      } else if (Better(fr_, f_[n - 1])) {  // better than the second worst: accept
        ReplaceWorst(xr_, fr_);
        break;
      } else if (Better(fr_, f_[n])) {  // between second worst and worst: outside
        pending_ = {Along(xr_, kContract, b)};
        phase_ = Phase::kContractOut;
      } else {  // no better than the worst: inside contraction
        pending_ = {Along(x_[n], kContract, b)};
        phase_ = Phase::kContractIn;
      }
      return;
    case Phase::kExpand:
      if (Better(evals[0], fr_)) {
        ReplaceWorst(pending_[0], evals[0]);
      } else {
        ReplaceWorst(xr_, fr_);
      }
      break;
    case Phase::kContractOut:
      if (!Better(fr_, evals[0])) {
        ReplaceWorst(pending_[0], evals[0]);
        break;
      }
      Shrink(b);
      return;
    case Phase::kContractIn:
      if (Better(evals[0], f_[n])) {
        ReplaceWorst(pending_[0], evals[0]);
        break;
      }
      Shrink(b);
      return;
    case Phase::kShrink:
      for (size_t k = 0; k < pending_.size(); ++k) {
        x_[k + 1] = pending_[k];
        f_[k + 1] = evals[k];
      }
      break;
    case Phase::kDone:
      return;
  }
  ++iterations_;
  BeginIteration(b, max_iterations, tolerance);
}

void NelderMead::Save(core::ByteWriter& w) const {
  w.U32(static_cast<uint32_t>(phase_));
  w.U64(x_.size());
  for (size_t v = 0; v < x_.size(); ++v) {
    w.F64s(x_[v]);
    WriteEvaluation(w, f_[v]);
  }
  w.F64s(centroid_);
  w.F64s(xr_);
  WriteEvaluation(w, fr_);
  w.U32(iterations_);
  w.U64(pending_.size());
  for (const auto& p : pending_) w.F64s(p);
}

std::optional<NelderMead> NelderMead::Load(core::ByteReader& r, size_t n) {
  NelderMead s;
  const uint32_t phase = r.U32();
  if (phase > static_cast<uint32_t>(Phase::kDone)) return std::nullopt;
  s.phase_ = static_cast<Phase>(phase);
  const uint64_t nv = r.U64();
  if (nv < 1 || nv > n + 1) return std::nullopt;
  for (uint64_t v = 0; v < nv; ++v) {
    s.x_.push_back(r.F64s());
    s.f_.push_back(ReadEvaluation(r));
    if (s.x_.back().size() != n) return std::nullopt;
  }
  s.centroid_ = r.F64s();
  s.xr_ = r.F64s();
  s.fr_ = ReadEvaluation(r);
  s.iterations_ = static_cast<int>(r.U32());
  const uint64_t np = r.U64();
  if (np > n) return std::nullopt;
  for (uint64_t k = 0; k < np; ++k) {
    s.pending_.push_back(r.F64s());
    if (s.pending_.back().size() != n) return std::nullopt;
  }
  if (!r.ok()) return std::nullopt;
  return s;
}

}  // namespace gaitforge::engines::sweep
