#include "workers/objectives/analytic.h"

#include <chrono>
#include <cmath>

namespace gaitforge::objectives {

double Sphere(const std::vector<double>& z) {
  double f = 0;
  for (double x : z) f += x * x;
  return f;
}

double Ellipsoid(const std::vector<double>& z) {
  const size_t n = z.size();
  double f = 0;
  for (size_t i = 0; i < n; ++i) {
    const double w = n > 1 ? std::pow(1e6, static_cast<double>(i) / (n - 1)) : 1.0;
    f += w * z[i] * z[i];
  }
  return f;
}

double Rosenbrock(const std::vector<double>& z) {
  double f = 0;
  for (size_t i = 0; i + 1 < z.size(); ++i) {
    const double a = z[i + 1] - z[i] * z[i];
    const double b = 1 - z[i];
    f += 100 * a * a + b * b;
  }
  return f;
}

double Rastrigin(const std::vector<double>& z) {
  double f = 10.0 * z.size();
  for (double x : z) f += x * x - 10 * std::cos(2 * M_PI * x);
  return f;
}

std::pair<double, double> Zdt1(const std::vector<double>& u) {
  double s = 0;
  for (size_t i = 1; i < u.size(); ++i) s += u[i];
  const double g = u.size() > 1 ? 1 + 9 * s / (u.size() - 1) : 1, f1 = u.empty() ? 0 : u[0];
  return {f1, g * (1 - std::sqrt(f1 / g))};
}

namespace {

// The genes mapped to [0, 1] by their ranges.
std::vector<double> UnitGenes(const EvalInput& in) {
  std::vector<double> u(in.genes.size());
  for (size_t i = 0; i < u.size(); ++i) u[i] = (in.genes[i] - in.lo[i]) / (in.hi[i] - in.lo[i]);
  return u;
}

class Zdt1Objective final : public Objective {
 public:
  EvalResult Evaluate(const EvalInput& in) const override {
    const auto [f1, f2] = Zdt1(UnitGenes(in));
    EvalResult r;
    r.valid = true;
    r.fitness = -(f1 + f2);
    r.metrics["f1"] = f1;
    r.metrics["f2"] = f2;
    return r;
  }
};

using LossFn = double (*)(const std::vector<double>&);

class Analytic final : public Objective {
 public:
  explicit Analytic(LossFn loss) : loss_(loss) {}

  EvalResult Evaluate(const EvalInput& in) const override {
    const auto get = [&](const char* k, double d) {
      auto it = in.params.find(k);
      return it == in.params.end() ? d : it->second;
    };
    const double shift = get("shift", 0.2);
    const double work_us = get("work_us", 0);
    const std::vector<double> u = UnitGenes(in);  // [0, 1)
    std::vector<double> z(u.size());
    for (size_t i = 0; i < z.size(); ++i) {
      const double unit = u[i];
      // Alternate the shift's sign so the optimum is off every diagonal.
      const double s = (i % 2 == 0 ? 1.0 : -1.0) * shift * 5.0;
      z[i] = 10.0 * unit - 5.0 - s;
    }
    if (work_us > 0) {
      // Emulates a simulator's cost (busy, like a physics step); does not touch the result.
      const auto until = std::chrono::steady_clock::now() +
                         std::chrono::nanoseconds(static_cast<int64_t>(work_us * 1000));
      while (std::chrono::steady_clock::now() < until) {
      }
    }
    EvalResult r;
    r.valid = true;
    const double loss = loss_(z);
    r.fitness = -loss;
    r.metrics["loss"] = loss;
    return r;
  }

 private:
  LossFn loss_;
};

}  // namespace

void RegisterAnalytic(ObjectiveRegistry& registry) {
  registry.Register("analytic.sphere", std::make_shared<Analytic>(&Sphere));
  registry.Register("analytic.ellipsoid", std::make_shared<Analytic>(&Ellipsoid));
  registry.Register("analytic.rosenbrock", std::make_shared<Analytic>(&Rosenbrock));
  registry.Register("analytic.rastrigin", std::make_shared<Analytic>(&Rastrigin));
  registry.Register("analytic.zdt1", std::make_shared<Zdt1Objective>());
}

}  // namespace gaitforge::objectives
