#include "services/engines/engine.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::engines {

double Bounds::Fold(size_t i, double x) const {
  if (!IsCircular(i)) return std::clamp(x, lo[i], hi[i]);
  const double period = hi[i] - lo[i];
  const double t = x - lo[i] - period * std::floor((x - lo[i]) / period);
  return t >= period ? lo[i] : lo[i] + t;  // rounding may reach the period
}

double Bounds::Near(size_t i, double x, double ref) const {
  if (!IsCircular(i)) return x;
  const double period = hi[i] - lo[i];
  return ref + std::remainder(x - ref, period);
}

absl::Status ValidateBounds(const Bounds& bounds) {
  if (bounds.size() == 0 || bounds.lo.size() != bounds.hi.size())
    return absl::InvalidArgumentError("bounds: at least one gene with lo and hi is required");
  for (size_t i = 0; i < bounds.size(); ++i) {
    const double lo = bounds.lo[i], hi = bounds.hi[i];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
      return absl::InvalidArgumentError(
          absl::StrCat("bounds[", i, "]: need finite lo < hi, got lo = ", lo, ", hi = ", hi));
  }
  return absl::OkStatus();
}

bool SameGenotype(const std::vector<double>& a, const std::vector<double>& b,
                  const Bounds& bounds) {
  if (a.size() != b.size() || a.size() != bounds.size()) return a == b;
  bool have_shift = false;
  double shift = 0;  // of the first circular gene, in periods
  for (size_t i = 0; i < a.size(); ++i) {
    const double range = bounds.hi[i] - bounds.lo[i], tol = 1e-9 * range;
    if (!bounds.IsCircular(i)) {
      if (std::abs(a[i] - b[i]) > tol) return false;
      continue;
    }
    const double d = std::remainder(a[i] - b[i], range) / range;
    if (!have_shift) {
      have_shift = true;
      shift = d;
    } else if (std::abs(std::remainder(d - shift, 1.0)) > 1e-9) {
      return false;
    }
  }
  return true;
}

bool RanksBefore(const Evaluation& a, int member_a, const Evaluation& b, int member_b) {
  if (a.valid != b.valid) return a.valid;
  if (a.valid) {
    const bool fa = a.violation <= 0.0, fb = b.violation <= 0.0;
    if (fa != fb) return fa;
    if (!fa && a.violation != b.violation) return a.violation < b.violation;
    if (fa && a.fitness != b.fitness) return a.fitness > b.fitness;
  }
  return member_a < member_b;
}

void WriteEvaluation(core::ByteWriter& w, const Evaluation& e) {
  w.U32(e.valid ? 1 : 0);
  w.F64(e.fitness);
  w.Str(e.reason);
  w.F64(e.violation);
}

Evaluation ReadEvaluation(core::ByteReader& r) {
  Evaluation e;
  e.valid = r.U32() != 0;
  e.fitness = r.F64();
  e.reason = r.Str();
  e.violation = r.F64();
  return e;
}

void WriteRanked(core::ByteWriter& w, const std::vector<Ranked>& v) {
  w.U64(v.size());
  for (const auto& h : v) {
    w.U32(h.generation);
    w.U32(h.member);
    w.F64s(h.genes);
    WriteEvaluation(w, h.eval);
  }
}

bool ReadRanked(core::ByteReader& r, std::vector<Ranked>& v, size_t cap, size_t n) {
  const uint64_t count = r.U64();
  if (count > cap) return false;
  v.resize(count);
  for (auto& h : v) {
    h.generation = static_cast<int>(r.U32());
    h.member = static_cast<int>(r.U32());
    h.genes = r.F64s();
    h.eval = ReadEvaluation(r);
    if (h.genes.size() != n) return false;
  }
  return r.ok();
}

}  // namespace gaitforge::engines
