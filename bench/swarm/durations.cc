#include "bench/swarm/durations.h"

#include <cmath>
#include <string_view>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace gaitforge::swarm {
namespace {

uint64_t Mix(uint64_t x) {  // splitmix64
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double Uniform(uint64_t h) { return (static_cast<double>(h >> 11) + 0.5) / 9007199254740992.0; }

}  // namespace

absl::StatusOr<Durations> Durations::Parse(const std::string& text) {
  std::vector<std::string> parts = absl::StrSplit(text, ':');
  Durations d;
  auto bad = [&] {
    return absl::InvalidArgumentError(absl::StrCat(
        "--eval '", text, "': expected constant:SECONDS or lognormal:MEAN_SECONDS:SIGMA"));
  };
  if (parts.size() == 2 && parts[0] == "constant") {
    if (!absl::SimpleAtod(parts[1], &d.mean_) || !(d.mean_ >= 0)) return bad();
    return d;
  }
  if (parts.size() == 3 && parts[0] == "lognormal") {
    if (!absl::SimpleAtod(parts[1], &d.mean_) || !absl::SimpleAtod(parts[2], &d.sigma_) ||
        !(d.mean_ > 0) || !(d.sigma_ >= 0) || d.sigma_ > 4)
      return bad();
    d.lognormal_ = true;
    return d;
  }
  return bad();
}

double Durations::Draw(const v1::JobKey& key) const {
  if (!lognormal_) return mean_;
  uint64_t h = Mix(std::hash<std::string_view>{}(key.study_id()));
  h = Mix(h ^ static_cast<uint64_t>(key.generation()) << 32 ^ static_cast<uint32_t>(key.member()));
  // Box-Muller from two uniforms of the key's hash.
  const double u1 = Uniform(h), u2 = Uniform(Mix(h));
  const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * M_PI * u2);
  const double mu = std::log(mean_) - sigma_ * sigma_ / 2;
  return std::exp(mu + sigma_ * z);
}

}  // namespace gaitforge::swarm
