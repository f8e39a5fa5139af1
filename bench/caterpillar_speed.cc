// Speed of the caterpillar model: simulated seconds per core-second and evaluations per
// second per thread for a 3 s gait (a travelling wave, T = 1 s, 2 settling + 1 measured
// cycle) at the timestep of caterpillar.yaml. Also prints every travelling wave's distance
// per cycle at T = 0.8 s. Plain program: figures on stdout.
#include <time.h>

#include <cstdio>
#include <string>

#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/sim/ode_runtime.h"

namespace {

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) {
    const bool help = std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h";
    std::fprintf(help ? stdout : stderr,
                 "usage: gaitforge-bench-caterpillar\n"
                 "Simulated seconds per core-second of the ODE caterpillar, evaluations per\n"
                 "second per thread of a 3 s gait, and every travelling wave's distance per\n"
                 "cycle at T = 0.8 s. No options.\n");
    return help ? 0 : 2;
  }
  using namespace gaitforge::caterpillar;
  gaitforge::sim::InitProcess();
  gaitforge::sim::InitThread();
  const CaterpillarParams& params = DefaultCaterpillarParams();
  const Gait gait = *Gait::FromGenes(TravellingWaveGenes(1.0));

  EvaluateGait(params, gait);  // warm-up
  const int kRuns = 20;
  double simulated = 0;
  const double t0 = CpuSeconds();
  for (int i = 0; i < kRuns; ++i) simulated += EvaluateGait(params, gait).simulated_s;
  const double cpu = CpuSeconds() - t0;
  std::printf("timestep_s %g\n", params.simulation.timestep_s);
  std::printf("simulated_s_per_core_s %.1f\n", simulated / cpu);
  std::printf("us_per_step %.2f\n", 1e6 * cpu / (simulated / params.simulation.timestep_s));
  std::printf("evaluations_per_s_per_thread_3s_gait %.1f\n", kRuns / cpu);

  EvalOptions many;
  many.measured_cycles = 20;
  // Every intuitive wave at T = 0.8 s, at h and h/2: caterpillar.md reports 0.7 to 1.1 cm per
  // cycle for a travelling wave in independent builds, and 6-16% of the time off the ground.
  for (const WaveShape& shape : WaveFamily()) {
    for (double h : {params.simulation.timestep_s, params.simulation.timestep_s / 2}) {
      many.timestep_s = h;
      const GaitEvaluation e = EvaluateGait(params, *Gait::FromGenes(WaveGenes(0.8, shape)), many);
      std::printf("wave_T0.8 %-26s h %-7g valid %d distance_per_cycle_cm %+.3f airborne %.3f "
                  "max_pitch_rad %.3f energy_per_cycle_j %.4f %s\n",
                  shape.Name().c_str(), h, e.valid, 100 * e.distance_per_cycle_m,
                  e.airborne_fraction, e.max_body_pitch_rad,
                  e.actuator_energy_j / many.measured_cycles, e.reason.c_str());
    }
  }
  return 0;
}
