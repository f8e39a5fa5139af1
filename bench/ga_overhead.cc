// The GA's own cost per generation: Ask + Tell for a population of 200 with 13 genes,
// evaluation excluded (fitness precomputed). Prints one JSON line for bench/foundation.py.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "robots/registry.h"
#include "services/core/objective_catalog.h"
#include "services/engines/ga/ga_engine.h"

using namespace gaitforge;

int main(int argc, char** argv) {
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf("usage: gaitforge-bench-ga [GENERATIONS]\n"
                "The GA's own cost per generation (Ask + Tell, 200 x 13 genes, default 2000\n"
                "generations), one JSON line; bench/foundation.py reads it.\n");
    return 0;
  }
  const int generations = argc > 1 ? std::atoi(argv[1]) : 2000;
  if (generations < 1) {
    std::fprintf(stderr, "gaitforge-bench-ga: GENERATIONS must be a positive integer\n");
    return 2;
  }
  engines::ga::GaConfig c;
  c.seed = 1;
  c.population = 200;
  c.generations = generations;
  for (const auto& g : core::GeneSpaceOf(robots::Robot("caterpillar"))) {
    c.bounds.lo.push_back(g.lo);
    c.bounds.hi.push_back(g.hi);
  }
  auto ga = std::move(*engines::ga::GaEngine::Create(c));
  std::vector<engines::Evaluation> evals(200);
  double total_s = 0;
  while (!ga->Done()) {
    const auto& cands = ga->Ask();
    // Fitness outside the timed region: a cheap function of the genes.
    for (size_t m = 0; m < cands.size(); ++m) {
      double f = 0;
      for (double x : cands[m].genes) f -= (x - 0.4) * (x - 0.4);
      evals[m] = {true, f, ""};
    }
    const auto t0 = std::chrono::steady_clock::now();
    (void)ga->Tell(evals);  // Tell breeds the next generation, which Ask then returns
    (void)ga->Ask();
    total_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::printf("{\"tool\":\"gaitforge-ga\",\"generations\":%d,\"ms_per_generation\":%.6f}\n",
              generations, 1000.0 * total_s / generations);
  return 0;
}
