#include "robots/onoff_waves.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::robots {
namespace {

double Wrap01(double x) {
  const double w = x - std::floor(x);
  return w >= 1.0 ? 0.0 : w;
}

}  // namespace

std::string WaveShape::Name() const {
  return absl::StrCat(front_first ? "head-first" : "tail-first",
                      interleaved ? " interleaved " : " rows ",
                      static_cast<int>(std::lround(100 * duty)), "%");
}

const std::vector<WaveShape>& WaveFamily() {
  static const std::vector<WaveShape> family = [] {
    std::vector<WaveShape> f;
    for (double duty : {0.5, 1.0 / 3.0})
      for (bool interleaved : {false, true})
        for (bool front_first : {false, true}) f.push_back({front_first, interleaved, duty});
    return f;
  }();
  return family;
}

std::vector<double> WaveGenes(int actuators, double period_s, const WaveShape& shape) {
  const int pairs = actuators / 2;
  const double slots = 2.0 * pairs;  // 6 for three pairs
  std::vector<double> g(2 * actuators + 1);
  for (int j = 0; j < pairs; ++j) {
    const int k = shape.front_first ? pairs - 1 - j : j;  // position of pair j in the wave
    const double top_on = shape.interleaved ? 2 * k / slots : k / slots;
    const double bottom_on = shape.interleaved ? (2 * k + 1) / slots : k / slots + 0.5;
    g[j] = Wrap01(top_on);                                      // a of top j
    g[actuators + j] = Wrap01(top_on + shape.duty);             // d of top j
    g[pairs + j] = Wrap01(bottom_on);                           // a of bottom j
    g[actuators + pairs + j] = Wrap01(bottom_on + shape.duty);  // d of bottom j
  }
  g[2 * actuators] = period_s;
  return g;
}

}  // namespace gaitforge::robots
