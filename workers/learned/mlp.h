#pragma once
// Learned models: a multilayer perceptron with its training (paper 004's adaptive model,
// which maps the arm's state to its joint parameters; paper 002's motor-current model).
// Inputs are standardised by their training mean and sd, hidden layers apply an
// activation, the output layer is linear, outputs are de-standardised. Training is
// full-batch Adam on the mean squared error of standardised outputs with an L2 weight
// penalty (in place of the paper's Bayesian regularisation), deterministic for a seed.
// File format: docs/learned-models.md.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "absl/status/statusor.h"

namespace gaitforge::learned {

enum class Activation { kLogSigmoid, kTanh, kRelu };

// "logsig", "tanh", "relu" and back; the error names the allowed ones.
std::string ActivationName(Activation a);
absl::StatusOr<Activation> ActivationOf(const std::string& name);

struct Layer {
  Eigen::MatrixXd w;  // outputs x inputs
  Eigen::VectorXd b;
};

struct Mlp {
  std::vector<std::string> inputs, outputs;  // names, for files and for whoever feeds it
  Activation activation = Activation::kLogSigmoid;
  std::vector<Layer> layers;  // hidden ones, then the linear output layer
  Eigen::VectorXd in_mean, in_sd, out_mean, out_sd;
  // The training rows' range of each input; an input outside it is held at its edge, so
  // that the net never extrapolates (a rate it never saw). Empty: no range.
  Eigen::VectorXd in_min{}, in_max{};

  // The outputs for x (inputs.size() values, in order).
  Eigen::VectorXd Eval(const Eigen::VectorXd& x) const;
  std::vector<double> operator()(const std::vector<double>& x) const;

  std::string ToJson() const;
  // The error names `source`, the key and what was expected.
  static absl::StatusOr<Mlp> FromJson(const std::string& text, const std::string& source);
};

struct TrainOptions {
  std::vector<int> hidden = {5};  // units per hidden layer (paper 004: one of 5)
  Activation activation = Activation::kLogSigmoid;
  int epochs = 3000;
  double learning_rate = 0.01;
  double weight_decay = 1e-4;   // L2 penalty on the weights (not the biases)
  double test_fraction = 0.3;   // held out, drawn with the seed (paper 004: 70/30)
  uint64_t seed = 1;
};

struct TrainReport {
  int train_n = 0, test_n = 0;
  // Pearson R of predictions against targets over every output (standardised, pooled),
  // and the mean squared error in standardised units, on each part.
  double train_r = 0, test_r = 0, train_mse = 0, test_mse = 0;
};

// Fits an Mlp to rows x (inputs) -> y (outputs). Errors: too few rows (fewer than 4), rows
// of the wrong width, non-finite values, a bad option (named with its allowed range).
absl::StatusOr<Mlp> Train(const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names,
                          const std::vector<std::vector<double>>& x,
                          const std::vector<std::vector<double>>& y, const TrainOptions& o,
                          TrainReport* report);

}  // namespace gaitforge::learned
