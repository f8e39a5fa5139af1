// Training an Mlp (mlp.h): full-batch Adam with an L2 weight penalty, deterministic per seed.
#include <cmath>
#include <numeric>
#include <random>

#include "absl/strings/str_cat.h"
#include "workers/learned/mlp.h"

namespace gaitforge::learned {
namespace {

// Uniform in [0, 1) from 53 bits: the same on every standard library.
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Eigen::MatrixXd Activated(Activation a, const Eigen::MatrixXd& z) {
  switch (a) {
    case Activation::kLogSigmoid: return (1.0 + (-z.array()).exp()).inverse().matrix();
    case Activation::kTanh: return z.array().tanh().matrix();
    case Activation::kRelu: return z.array().max(0.0).matrix();
  }
  return z;
}

// The activation's derivative from its output a (and input z, for relu).
Eigen::MatrixXd Slope(Activation act, const Eigen::MatrixXd& a, const Eigen::MatrixXd& z) {
  switch (act) {
    case Activation::kLogSigmoid: return (a.array() * (1 - a.array())).matrix();
    case Activation::kTanh: return (1 - a.array().square()).matrix();
    case Activation::kRelu: return (z.array() > 0).cast<double>().matrix();
  }
  return a;
}

// Columns `rows` of the data, standardised by mean and sd.
Eigen::MatrixXd Columns(const std::vector<std::vector<double>>& rows, const std::vector<size_t>& pick,
                        const Eigen::VectorXd& mean, const Eigen::VectorXd& sd) {
  Eigen::MatrixXd m(mean.size(), pick.size());
  for (size_t j = 0; j < pick.size(); ++j)
    for (Eigen::Index i = 0; i < mean.size(); ++i) m(i, j) = (rows[pick[j]][i] - mean[i]) / sd[i];
  return m;
}

void Standardisation(const std::vector<std::vector<double>>& rows, const std::vector<size_t>& pick,
                     Eigen::VectorXd& mean, Eigen::VectorXd& sd) {
  const size_t n = rows.front().size();
  mean = Eigen::VectorXd::Zero(n);
  sd = Eigen::VectorXd::Zero(n);
  for (size_t j : pick)
    for (size_t i = 0; i < n; ++i) mean[i] += rows[j][i] / pick.size();
  for (size_t j : pick)
    for (size_t i = 0; i < n; ++i) sd[i] += std::pow(rows[j][i] - mean[i], 2) / pick.size();
  for (size_t i = 0; i < n; ++i) sd[i] = sd[i] > 1e-24 ? std::sqrt(sd[i]) : 1.0;
}

// Forward pass over standardised columns: every layer's output (the last linear).
std::vector<Eigen::MatrixXd> Forward(const Mlp& m, const Eigen::MatrixXd& x,
                                     std::vector<Eigen::MatrixXd>* pre = nullptr) {
  std::vector<Eigen::MatrixXd> a{x};
  for (size_t l = 0; l < m.layers.size(); ++l) {
    Eigen::MatrixXd z = (m.layers[l].w * a.back()).colwise() + m.layers[l].b;
    if (pre) pre->push_back(z);
    a.push_back(l + 1 < m.layers.size() ? Activated(m.activation, z) : z);
  }
  return a;
}

double PearsonR(const Eigen::MatrixXd& p, const Eigen::MatrixXd& y) {
  const Eigen::ArrayXd a = Eigen::Map<const Eigen::ArrayXd>(p.data(), p.size());
  const Eigen::ArrayXd b = Eigen::Map<const Eigen::ArrayXd>(y.data(), y.size());
  const Eigen::ArrayXd da = a - a.mean(), db = b - b.mean();
  const double den = std::sqrt((da * da).sum() * (db * db).sum());
  return den > 0 ? (da * db).sum() / den : 0.0;
}

// One Adam moment pair per parameter block.
struct Adam {
  Eigen::MatrixXd m, v;
  void Step(Eigen::MatrixXd& p, const Eigen::MatrixXd& g, double lr, int t) {
    if (m.size() == 0) m = v = Eigen::MatrixXd::Zero(p.rows(), p.cols());
    m = 0.9 * m + 0.1 * g;
    v = 0.999 * v + 0.001 * g.cwiseProduct(g);
    const double c1 = 1 - std::pow(0.9, t), c2 = 1 - std::pow(0.999, t);
    p.array() -= lr * (m.array() / c1) / ((v.array() / c2).sqrt() + 1e-8);
  }
};

void Epoch(Mlp& m, const Eigen::MatrixXd& x, const Eigen::MatrixXd& y, const TrainOptions& o,
           std::vector<Adam>& adam, int t) {
  std::vector<Eigen::MatrixXd> pre;
  const std::vector<Eigen::MatrixXd> a = Forward(m, x, &pre);
  Eigen::MatrixXd delta = 2.0 * (a.back() - y) / static_cast<double>(y.size());
  for (size_t l = m.layers.size(); l-- > 0;) {
    Eigen::MatrixXd gw = delta * a[l].transpose() + 2 * o.weight_decay * m.layers[l].w;
    Eigen::MatrixXd gb = delta.rowwise().sum();
    if (l > 0)
      delta = (m.layers[l].w.transpose() * delta).cwiseProduct(Slope(m.activation, a[l], pre[l - 1]));
    adam[2 * l].Step(m.layers[l].w, gw, o.learning_rate, t);
    Eigen::MatrixXd b = m.layers[l].b;
    adam[2 * l + 1].Step(b, gb, o.learning_rate, t);
    m.layers[l].b = b;
  }
}

absl::Status Check(const std::vector<std::vector<double>>& x, const std::vector<std::vector<double>>& y,
                   size_t n_in, size_t n_out, const TrainOptions& o) {
  if (x.size() != y.size() || x.size() < 4)
    return absl::InvalidArgumentError(absl::StrCat("training needs at least 4 rows of inputs and "
                                                   "outputs alike, got ", x.size(), " and ", y.size()));
  for (size_t j = 0; j < x.size(); ++j) {
    if (x[j].size() != n_in || y[j].size() != n_out)
      return absl::InvalidArgumentError(absl::StrCat("row ", j, " has ", x[j].size(), " inputs and ",
                                                     y[j].size(), " outputs, not ", n_in, " and ", n_out));
    for (double v : x[j]) if (!std::isfinite(v)) return absl::InvalidArgumentError(absl::StrCat("row ", j, ": an input is not finite"));
    for (double v : y[j]) if (!std::isfinite(v)) return absl::InvalidArgumentError(absl::StrCat("row ", j, ": an output is not finite"));
  }
  if (!(o.test_fraction >= 0 && o.test_fraction < 0.9))
    return absl::InvalidArgumentError(absl::StrCat("test_fraction ", o.test_fraction, " is outside [0, 0.9)"));
  if (o.epochs < 1 || o.epochs > 10000000 || !(o.learning_rate > 0) || o.weight_decay < 0 || o.hidden.empty())
    return absl::InvalidArgumentError("epochs 1..1e7, learning_rate > 0, weight_decay >= 0 and at least one hidden layer");
  for (int h : o.hidden)
    if (h < 1 || h > 4096) return absl::InvalidArgumentError(absl::StrCat("a hidden layer of ", h, " units (1..4096)"));
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<Mlp> Train(const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names,
                          const std::vector<std::vector<double>>& x,
                          const std::vector<std::vector<double>>& y, const TrainOptions& o,
                          TrainReport* report) {
  if (auto s = Check(x, y, input_names.size(), output_names.size(), o); !s.ok()) return s;
  std::mt19937_64 rng(o.seed);
  std::vector<size_t> order(x.size());
  std::iota(order.begin(), order.end(), 0);
  for (size_t i = order.size(); i-- > 1;) std::swap(order[i], order[static_cast<size_t>(Uniform(rng) * (i + 1))]);
  const size_t n_test = static_cast<size_t>(std::floor(o.test_fraction * x.size()));
  const std::vector<size_t> test(order.begin(), order.begin() + n_test), train(order.begin() + n_test, order.end());
  Mlp m{input_names, output_names, o.activation, {}, {}, {}, {}, {}};
  Standardisation(x, train, m.in_mean, m.in_sd);
  m.in_min = m.in_max = Eigen::Map<const Eigen::VectorXd>(x[train.front()].data(), x[train.front()].size());
  for (size_t j : train) {
    const Eigen::Map<const Eigen::VectorXd> row(x[j].data(), x[j].size());
    m.in_min = m.in_min.cwiseMin(row);
    m.in_max = m.in_max.cwiseMax(row);
  }
  Standardisation(y, train, m.out_mean, m.out_sd);
  int width = static_cast<int>(input_names.size());
  std::vector<int> sizes = o.hidden;
  sizes.push_back(static_cast<int>(output_names.size()));
  for (int units : sizes) {
    const double r = std::sqrt(6.0 / (width + units));  // Glorot uniform
    Layer layer{Eigen::MatrixXd(units, width), Eigen::VectorXd::Zero(units)};
    for (Eigen::Index i = 0; i < layer.w.size(); ++i) layer.w.data()[i] = r * (2 * Uniform(rng) - 1);
    m.layers.push_back(std::move(layer));
    width = units;
  }
  const Eigen::MatrixXd xt = Columns(x, train, m.in_mean, m.in_sd), yt = Columns(y, train, m.out_mean, m.out_sd);
  std::vector<Adam> adam(2 * m.layers.size());
  for (int t = 1; t <= o.epochs; ++t) Epoch(m, xt, yt, o, adam, t);
  if (report) {
    report->train_n = static_cast<int>(train.size());
    report->test_n = static_cast<int>(test.size());
    const Eigen::MatrixXd pt = Forward(m, xt).back();
    report->train_r = PearsonR(pt, yt);
    report->train_mse = (pt - yt).squaredNorm() / yt.size();
    if (!test.empty()) {
      const Eigen::MatrixXd xs = Columns(x, test, m.in_mean, m.in_sd), ys = Columns(y, test, m.out_mean, m.out_sd);
      const Eigen::MatrixXd ps = Forward(m, xs).back();
      report->test_r = PearsonR(ps, ys);
      report->test_mse = (ps - ys).squaredNorm() / ys.size();
    }
  }
  return m;
}

}  // namespace gaitforge::learned
