// A multilayer perceptron: evaluation and its file (mlp.h).
#include "workers/learned/mlp.h"

#include <cmath>

#include <yaml-cpp/yaml.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::learned {
namespace {

constexpr const char* kFormat = "gaitforge.mlp.v1";

Eigen::VectorXd Activate(Activation a, const Eigen::VectorXd& z) {
  switch (a) {
    case Activation::kLogSigmoid: return (1.0 + (-z.array()).exp()).inverse().matrix();
    case Activation::kTanh: return z.array().tanh().matrix();
    case Activation::kRelu: return z.array().max(0.0).matrix();
  }
  return z;
}

std::string Numbers(const Eigen::VectorXd& v) {
  std::vector<std::string> parts;
  for (Eigen::Index i = 0; i < v.size(); ++i) parts.push_back(absl::StrFormat("%.17g", v[i]));
  return absl::StrCat("[", absl::StrJoin(parts, ", "), "]");
}

std::string Quoted(const std::vector<std::string>& names) {
  std::vector<std::string> parts;
  for (const auto& n : names) parts.push_back(absl::StrCat("\"", n, "\""));
  return absl::StrCat("[", absl::StrJoin(parts, ", "), "]");
}

absl::Status Bad(const std::string& source, const std::string& key, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(source, ": key '", key, "': ", what));
}

absl::StatusOr<Eigen::VectorXd> Vector(const YAML::Node& n, const std::string& source,
                                       const std::string& key, Eigen::Index size) {
  if (!n || !n.IsSequence() || static_cast<Eigen::Index>(n.size()) != size)
    return Bad(source, key, absl::StrCat("expected a list of ", size, " numbers"));
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) {
    v[i] = n[i].as<double>();
    if (!std::isfinite(v[i])) return Bad(source, key, "numbers must be finite");
  }
  return v;
}

}  // namespace

std::string ActivationName(Activation a) {
  switch (a) {
    case Activation::kLogSigmoid: return "logsig";
    case Activation::kTanh: return "tanh";
    case Activation::kRelu: return "relu";
  }
  return "?";
}

absl::StatusOr<Activation> ActivationOf(const std::string& name) {
  for (Activation a : {Activation::kLogSigmoid, Activation::kTanh, Activation::kRelu})
    if (ActivationName(a) == name) return a;
  return absl::InvalidArgumentError(
      absl::StrCat("activation '", name, "' is not one of logsig, tanh, relu"));
}

Eigen::VectorXd Mlp::Eval(const Eigen::VectorXd& x) const {
  Eigen::VectorXd held = x;
  if (in_min.size() == x.size()) held = x.cwiseMax(in_min).cwiseMin(in_max);
  Eigen::VectorXd a = (held - in_mean).cwiseQuotient(in_sd);
  for (size_t l = 0; l < layers.size(); ++l) {
    a = layers[l].w * a + layers[l].b;
    if (l + 1 < layers.size()) a = Activate(activation, a);
  }
  return a.cwiseProduct(out_sd) + out_mean;
}

std::vector<double> Mlp::operator()(const std::vector<double>& x) const {
  const Eigen::VectorXd y = Eval(Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()));
  return std::vector<double>(y.data(), y.data() + y.size());
}

std::string Mlp::ToJson() const {
  std::string json = absl::StrCat("{\n \"format\": \"", kFormat, "\",\n \"inputs\": ",
                                  Quoted(inputs), ",\n \"outputs\": ", Quoted(outputs),
                                  ",\n \"activation\": \"", ActivationName(activation), "\",\n");
  absl::StrAppend(&json, " \"input_mean\": ", Numbers(in_mean), ",\n \"input_sd\": ",
                  Numbers(in_sd), ",\n \"output_mean\": ", Numbers(out_mean),
                  ",\n \"output_sd\": ", Numbers(out_sd), ",\n");
  if (in_min.size() > 0)
    absl::StrAppend(&json, " \"input_min\": ", Numbers(in_min), ",\n \"input_max\": ", Numbers(in_max), ",\n");
  absl::StrAppend(&json, " \"layers\": [");
  for (size_t l = 0; l < layers.size(); ++l) {
    std::vector<std::string> rows;
    for (Eigen::Index r = 0; r < layers[l].w.rows(); ++r)
      rows.push_back(Numbers(layers[l].w.row(r).transpose()));
    absl::StrAppend(&json, l ? ",\n" : "\n", "  {\"weights\": [", absl::StrJoin(rows, ", "),
                    "],\n   \"bias\": ", Numbers(layers[l].b), "}");
  }
  return absl::StrCat(json, "\n ]\n}\n");
}

absl::StatusOr<Mlp> Mlp::FromJson(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ": ", e.msg));
  }
  if (!root.IsMap() || !root["format"] || root["format"].as<std::string>() != kFormat)
    return Bad(source, "format", absl::StrCat("expected \"", kFormat, "\""));
  Mlp m;
  try {
    m.inputs = root["inputs"].as<std::vector<std::string>>();
    m.outputs = root["outputs"].as<std::vector<std::string>>();
    auto act = ActivationOf(root["activation"].as<std::string>());
    if (!act.ok()) return Bad(source, "activation", std::string(act.status().message()));
    m.activation = *act;
    const Eigen::Index n_in = m.inputs.size(), n_out = m.outputs.size();
    if (n_in == 0 || n_out == 0) return Bad(source, "inputs", "inputs and outputs must be named");
    for (auto [key, size, out] : {std::tuple{"input_mean", n_in, &m.in_mean},
                                  std::tuple{"input_sd", n_in, &m.in_sd},
                                  std::tuple{"output_mean", n_out, &m.out_mean},
                                  std::tuple{"output_sd", n_out, &m.out_sd}}) {
      auto v = Vector(root[key], source, key, size);
      if (!v.ok()) return v.status();
      *out = *v;
    }
    if (root["input_min"] || root["input_max"]) {
      auto lo = Vector(root["input_min"], source, "input_min", n_in);
      if (!lo.ok()) return lo.status();
      auto hi = Vector(root["input_max"], source, "input_max", n_in);
      if (!hi.ok()) return hi.status();
      if (!(lo->array() <= hi->array()).all()) return Bad(source, "input_min", "must not exceed input_max");
      m.in_min = *lo;
      m.in_max = *hi;
    }
    if (!(m.in_sd.array() > 0).all() || !(m.out_sd.array() > 0).all())
      return Bad(source, "input_sd", "every sd must be > 0");
    Eigen::Index width = n_in;
    const YAML::Node layers = root["layers"];
    if (!layers.IsSequence() || layers.size() == 0) return Bad(source, "layers", "expected a list");
    for (size_t l = 0; l < layers.size(); ++l) {
      const std::string key = absl::StrCat("layers[", l, "]");
      const YAML::Node w = layers[l]["weights"];
      if (!w.IsSequence() || w.size() == 0) return Bad(source, key + ".weights", "expected rows");
      Layer layer{Eigen::MatrixXd(w.size(), width), {}};
      for (size_t r = 0; r < w.size(); ++r) {
        auto row = Vector(w[r], source, absl::StrCat(key, ".weights[", r, "]"), width);
        if (!row.ok()) return row.status();
        layer.w.row(r) = row->transpose();
      }
      auto b = Vector(layers[l]["bias"], source, key + ".bias", layer.w.rows());
      if (!b.ok()) return b.status();
      layer.b = *b;
      width = layer.w.rows();
      m.layers.push_back(std::move(layer));
    }
    if (width != n_out)
      return Bad(source, "layers", absl::StrCat("the last layer gives ", width, " values for ",
                                                n_out, " outputs"));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ": ", e.msg));
  }
  return m;
}

}  // namespace gaitforge::learned
