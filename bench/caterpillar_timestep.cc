// How faithful is the caterpillar (on the generic builder) at each timestep, and what does it cost? For a fixed
// sample of random 13-gene gaits (the GA's initial population distribution, seed 1) and the
// eight travelling waves at five periods, the distance per cycle (mean over --cycles after 2
// settling cycles) at h = 0.2 (the reference) .. 2 ms. Per h: the median and 90th percentile
// of |d_h - d_ref| in cm per cycle, the rank correlation with the reference, how many of the
// reference's best 10% stay in the best 10%, invalid runs, and simulated s per core-second.
// The hopping robot is chaotic in h (caterpillar.md), so the deviation of h = 0.25 ms from
// 0.2 ms is the noise floor: a timestep whose deviation is near it is as faithful as any.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "robots/onoff_waves.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/sim/ode_runtime.h"

namespace {

using gaitforge::generic::GaitOptions;
using gaitforge::generic::GaitResult;

double ThreadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

std::vector<double> Ranks(const std::vector<double>& v) {
  std::vector<size_t> order(v.size());
  for (size_t i = 0; i < v.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (size_t i = 0; i < order.size(); ++i) r[order[i]] = static_cast<double>(i);
  return r;
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

double Quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1) + 0.5)];
}

struct Column {
  double h = 0;
  std::vector<double> distance;  // m per cycle, NAN when invalid
  double simulated_s = 0, cpu_s = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int count = 160, cycles = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: gaitforge-bench-timestep [--gaits N] [--cycles C]\n"
          "Distance per cycle of N random gaits (default 160) and 40 travelling waves at\n"
          "h = 0.2, 0.25, 0.5, 1, 1.5, 2 ms, mean over C measured cycles (default 5); per h\n"
          "the deviation from h = 0.2 ms, rank correlation, top-10%% overlap, invalid runs\n"
          "and simulated seconds per core-second. Runs on 2 threads.\n");
      return 0;
    }
    if ((a == "--gaits" || a == "--cycles") && i + 1 < argc) {
      const int v = std::atoi(argv[++i]);
      if (v < 1 || v > 100000) {
        std::fprintf(stderr, "%s: must lie in [1, 100000], got %s\n", a.c_str(), argv[i]);
        return 2;
      }
      (a == "--gaits" ? count : cycles) = v;
      continue;
    }
    std::fprintf(stderr, "unknown argument %s (see --help)\n", a.c_str());
    return 2;
  }
  gaitforge::sim::InitProcess();
  const auto& robot = gaitforge::robots::Robot("caterpillar");
  const gaitforge::generic::ParamValues values(robot);

  // Random genotypes over the gene space (phases in [0, 1], T in [0.2, 2] s).
  std::vector<std::vector<double>> genes;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < count; ++i) {
    std::vector<double> g;
    for (const auto& gene : robot.controller.genes) g.push_back(gene.lo + (gene.hi - gene.lo) * unit(rng));
    genes.push_back(g);
  }
  const int actuators = static_cast<int>(robot.controller.actuators.size());
  for (const auto& shape : gaitforge::robots::WaveFamily()) {
    for (double T : {0.4, 0.6, 0.8, 1.2, 1.6})
      genes.push_back(gaitforge::robots::WaveGenes(actuators, T, shape));
  }

  std::vector<Column> columns;
  for (double h : {2e-4, 2.5e-4, 5e-4, 1e-3, 1.5e-3, 2e-3}) columns.push_back({h, {}, 0, 0});
  for (Column& c : columns) {
    c.distance.assign(genes.size(), NAN);
    double simulated[2] = {0, 0}, cpu[2] = {0, 0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 2; ++t) {
      threads.emplace_back([&, t] {
        gaitforge::sim::InitThread();
        GaitOptions o;
        o.timestep_s = c.h;
        o.measured_cycles = cycles;
        const double t0 = ThreadCpuSeconds();
        for (size_t i = t; i < genes.size(); i += 2) {
          const GaitResult e = gaitforge::generic::EvaluateGait(robot, values, genes[i], o);
          simulated[t] += e.simulated_s;
          if (e.valid) c.distance[i] = e.distance_per_cycle_m;
        }
        cpu[t] = ThreadCpuSeconds() - t0;
      });
    }
    for (auto& th : threads) th.join();
    c.simulated_s = simulated[0] + simulated[1];
    c.cpu_s = cpu[0] + cpu[1];
    std::fprintf(stderr, "h = %g ms done\n", 1e3 * c.h);
  }

  const Column& ref = columns.front();
  const size_t top = std::max<size_t>(1, genes.size() / 10);
  std::printf("gaits %zu (random %d + waves %zu), measured cycles %d, reference h = %g ms\n",
              genes.size(), count, genes.size() - count, cycles, 1e3 * ref.h);
  std::printf("%-7s %12s %12s %10s %9s %8s %8s %10s\n", "h_ms", "med|dd|_cm", "p90|dd|_cm",
              "spearman", "top10%", "invalid", "mean_cm", "sim_s/cpu_s");
  for (const Column& c : columns) {
    std::vector<double> dev, a, b;
    int invalid = 0;
    double mean = 0;
    for (size_t i = 0; i < genes.size(); ++i) {
      if (std::isnan(c.distance[i])) ++invalid;
      if (std::isnan(c.distance[i]) || std::isnan(ref.distance[i])) continue;
      dev.push_back(100 * std::fabs(c.distance[i] - ref.distance[i]));
      a.push_back(c.distance[i]);
      b.push_back(ref.distance[i]);
      mean += 100 * c.distance[i];
    }
    mean /= static_cast<double>(a.size());
    const std::vector<double> ra = Ranks(a), rb = Ranks(b);
    size_t overlap = 0;
    const double cut = static_cast<double>(a.size() - top);
    for (size_t i = 0; i < a.size(); ++i) overlap += ra[i] >= cut && rb[i] >= cut;
    std::printf("%-7g %12.3f %12.3f %10.4f %6zu/%zu %8d %8.3f %10.1f\n", 1e3 * c.h,
                Quantile(dev, 0.5), Quantile(dev, 0.9), Correlation(ra, rb), overlap, top,
                invalid, mean, c.simulated_s / c.cpu_s);
  }
  return 0;
}
