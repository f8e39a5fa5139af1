#include "services/core/keyed_rng.h"

#include <cmath>

namespace gaitforge::core {

uint64_t Mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

KeyedRng::KeyedRng(uint64_t seed, uint64_t generation, uint64_t member, Purpose purpose) {
  uint64_t s = Mix64(seed);
  s = Mix64(s ^ (generation * 0xd1b54a32d192ed03ULL));
  s = Mix64(s ^ (member * 0xabc98388fb8fac03ULL));
  s = Mix64(s ^ (static_cast<uint64_t>(purpose) * 0x8cb92ba72f3d8dd7ULL));
  state_ = s;
}

uint64_t KeyedRng::NextU64() {
  uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double KeyedRng::Uniform01() {
  return static_cast<double>(NextU64() >> 11) * 0x1.0p-53;
}

double KeyedRng::Uniform(double lo, double hi) {
  double x = lo + (hi - lo) * Uniform01();
  // Rounding can land exactly on hi when the range is tiny; keep the interval half-open.
  return x < hi ? x : lo;
}

int64_t KeyedRng::UniformInt(int64_t lo, int64_t hi) {
  const uint64_t span = static_cast<uint64_t>(hi - lo) + 1;
  if (span == 0) return static_cast<int64_t>(NextU64());  // full 64-bit range
  const uint64_t limit = UINT64_MAX - (UINT64_MAX % span);
  uint64_t r;
  do {
    r = NextU64();
  } while (r >= limit);
  return lo + static_cast<int64_t>(r % span);
}

double KeyedRng::Normal() {
  double u1 = Uniform01();
  double u2 = Uniform01();
  if (u1 <= 0.0) u1 = 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace gaitforge::core
