#pragma once
// A counter-based random stream keyed by (study seed, generation, member, purpose).
//
// Contract: the numbers a KeyedRng yields depend only on its key, never on how many other
// streams exist or in which order they are used. This is what makes a study independent of
// worker count, timing and restarts (../shared/guides/design.md, "Determinism").
// The generator is SplitMix64 (Steele, Lea, Flood 2014) over a state derived by mixing
// the key; its output passes BigCrush and needs no global state.
#include <cstdint>

namespace gaitforge::core {

// Why a random number is drawn. Values are part of the on-disk contract: never renumber.
enum class Purpose : uint64_t {
  kInit = 1,        // initial population genes
  kSelect = 2,      // roulette-wheel parent selection
  kCrossover = 3,   // the crossover point of a generation
  kMutate = 4,      // per-gene mutation decisions and fresh values
  kEngine = 5,      // other engine decisions (CMA-ES sampling, restarts)
  kEnsemble = 6,    // robust evaluation's parameter samples (workers/objectives/ensemble.h)
  kPlan = 7,        // random gaits a diagnosis plan proposes (services/diagnosis/plan.h)
};

class KeyedRng {
 public:
  KeyedRng(uint64_t seed, uint64_t generation, uint64_t member, Purpose purpose);

  uint64_t NextU64();
  // Uniform in [0, 1) with 53 random bits.
  double Uniform01();
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi);
  // Uniform integer in [lo, hi], unbiased (rejection sampling).
  int64_t UniformInt(int64_t lo, int64_t hi);
  // Standard normal (Box-Muller on two uniforms; no cached spare, so streams stay keyed).
  double Normal();

 private:
  uint64_t state_;
};

// The SplitMix64 finaliser: a bijective 64-bit mix.
uint64_t Mix64(uint64_t x);

}  // namespace gaitforge::core
