#include "workers/models/caterpillar/caterpillar_params.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace gaitforge::caterpillar {
namespace {

using P = CaterpillarParams;

// One numeric field: its dotted path in the file, unit, allowed closed range, and where it
// goes. `integer` fields must hold whole numbers.
struct Field {
  const char* path;
  const char* unit;
  double lo, hi;
  std::function<void(P&, double)> set;
  bool integer = false;
};

#define GF_FIELD(path, unit, lo, hi, member) \
  Field { path, unit, lo, hi, [](P& p, double v) { p.member = v; } }

const std::vector<Field>& Fields() {
  static const std::vector<Field> fields = {
      GF_FIELD("lumps.mass_kg", "kg", 0.001, 1, lumps.mass_kg),
      GF_FIELD("lumps.size_x_m", "m", 0.005, 0.2, lumps.size_x_m),
      GF_FIELD("lumps.size_y_m", "m", 0.005, 0.2, lumps.size_y_m),
      GF_FIELD("lumps.size_z_m", "m", 0.005, 0.2, lumps.size_z_m),
      GF_FIELD("lumps.spacing_m", "m", 0.005, 0.5, lumps.spacing_m),
      GF_FIELD("links.flexure.axial_stiffness_n_per_m", "N/m", 1, 1e6,
               links.flexure.axial_n_per_m),
      GF_FIELD("links.flexure.bending_stiffness_nm_per_rad", "N m/rad", 1e-4, 100,
               links.flexure.bending_nm_per_rad),
      GF_FIELD("links.segment.axial_stiffness_n_per_m", "N/m", 1, 1e6,
               links.segment.axial_n_per_m),
      GF_FIELD("links.segment.bending_stiffness_nm_per_rad", "N m/rad", 1e-4, 100,
               links.segment.bending_nm_per_rad),
      GF_FIELD("links.axial_damping_ratio", "of critical", 0.01, 10,
               links.axial_damping_ratio),
      GF_FIELD("links.bending_damping_ratio", "of critical", 0.01, 10,
               links.bending_damping_ratio),
      GF_FIELD("actuators.force_n", "N", 0, 100, actuators.force_n),
      GF_FIELD("actuators.return_spring_n_per_m", "N/m", 0, 1e4,
               actuators.return_spring_n_per_m),
      GF_FIELD("actuators.min_length_m", "m", 0.001, 1, actuators.min_length_m),
      GF_FIELD("actuators.max_length_m", "m", 0.001, 1, actuators.max_length_m),
      GF_FIELD("actuators.rear_attach_x_m", "m", -0.1, 0.1, actuators.rear_attach_x_m),
      GF_FIELD("actuators.front_attach_x_m", "m", -0.1, 0.1, actuators.front_attach_x_m),
      GF_FIELD("actuators.top_attach_z_m", "m", -0.1, 0.1, actuators.top_attach_z_m),
      GF_FIELD("actuators.bottom_attach_z_m", "m", -0.1, 0.1, actuators.bottom_attach_z_m),
      GF_FIELD("actuators.stop_erp", "", 0.01, 1, actuators.stop_erp),
      GF_FIELD("actuators.stop_cfm", "", 0, 1e-2, actuators.stop_cfm),
      GF_FIELD("actuators.overrun_tolerance_m", "m", 1e-5, 0.05,
               actuators.overrun_tolerance_m),
      GF_FIELD("ground.contact_erp", "", 0.01, 1, ground.contact_erp),
      GF_FIELD("ground.contact_cfm", "", 0, 1e-2, ground.contact_cfm),
      GF_FIELD("markers.offset_x_m", "m", -0.1, 0.1, markers.offset_x_m),
      GF_FIELD("markers.offset_z_m", "m", -0.1, 0.1, markers.offset_z_m),
      GF_FIELD("simulation.gravity_m_per_s2", "m/s^2", 0, 100, simulation.gravity_m_per_s2),
      GF_FIELD("simulation.timestep_s", "s", 5e-5, 0.002, simulation.timestep_s),
      Field{"simulation.settle_cycles", "cycles", 0, 20,
            [](P& p, double v) { p.simulation.settle_cycles = static_cast<int>(v); }, true},
      Field{"simulation.measured_cycles", "cycles", 1, 50,
            [](P& p, double v) { p.simulation.measured_cycles = static_cast<int>(v); }, true},
      GF_FIELD("simulation.solver_erp", "", 0.01, 1, simulation.solver_erp),
      GF_FIELD("simulation.solver_cfm", "", 0, 1e-3, simulation.solver_cfm),
      GF_FIELD("simulation.max_speed_m_per_s", "m/s", 0.1, 1e4,
               simulation.max_speed_m_per_s),
      GF_FIELD("simulation.max_excursion_m", "m", 0.01, 1e4, simulation.max_excursion_m),
  };
  return fields;
}
#undef GF_FIELD

constexpr char kFormat[] = "gaitforge.caterpillar.v1";
constexpr char kFrictionPath[] = "ground.friction";
constexpr double kFrictionMax = 10;

std::string Where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return source;
  return absl::StrCat(source, ":", mark.line + 1);
}

std::string Range(const Field& f) {
  std::ostringstream out;
  out << "[" << f.lo << ", " << f.hi << "]" << (*f.unit ? " " : "") << f.unit;
  return out.str();
}

// The node at a dotted path; an invalid node when absent.
YAML::Node Lookup(const YAML::Node& root, const std::string& path) {
  // Node::operator= would assign into the tree; reset() rebinds the handle.
  YAML::Node node;
  node.reset(root);
  for (const auto& key : absl::StrSplit(path, '.')) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node child = static_cast<const YAML::Node&>(node)[std::string(key)];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);
  }
  return node;
}

// Unknown keys are errors: a misspelt field would otherwise silently keep nothing.
void CollectKeys(const YAML::Node& node, const std::string& prefix,
                 std::vector<std::pair<std::string, YAML::Node>>& out) {
  for (const auto& kv : node) {
    const std::string key = prefix.empty() ? kv.first.Scalar() : prefix + "." + kv.first.Scalar();
    if (kv.second.IsMap()) {
      CollectKeys(kv.second, key, out);
    } else {
      out.emplace_back(key, kv.first);
    }
  }
}

absl::Status Invalid(const std::string& where, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(where, ": ", what));
}

absl::StatusOr<CaterpillarParams> FromYaml(const YAML::Node& root, const std::string& source) {
  if (!root.IsMap()) return Invalid(source, "expected a mapping of the model's fields");
  std::set<std::string> known = {"format", kFrictionPath};
  for (const auto& f : Fields()) known.insert(f.path);
  std::vector<std::pair<std::string, YAML::Node>> keys;
  CollectKeys(root, "", keys);
  for (const auto& [key, node] : keys) {
    if (!known.count(key)) return Invalid(Where(source, node), "unknown field " + key);
  }
  const YAML::Node format = root["format"];
  if (!format || !format.IsScalar() || format.Scalar() != kFormat) {
    return Invalid(format ? Where(source, format) : source,
                   absl::StrCat("field format must be \"", kFormat, "\""));
  }

  CaterpillarParams p;
  for (const Field& f : Fields()) {
    const YAML::Node node = Lookup(root, f.path);
    if (!node.IsDefined()) {
      return Invalid(source, absl::StrCat("missing field ", f.path, " (", f.unit, ", range ",
                                          Range(f), ")"));
    }
    double v = 0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || !std::isfinite(v)) {
      return Invalid(Where(source, node),
                     absl::StrCat(f.path, " must be a number in ", Range(f)));
    }
    if (v < f.lo || v > f.hi || (f.integer && v != std::floor(v))) {
      return Invalid(Where(source, node),
                     absl::StrCat(f.path, " = ", node.Scalar(), *f.unit ? " " : "", f.unit,
                                  " is outside ", Range(f),
                                  f.integer ? " (a whole number)" : ""));
    }
    f.set(p, v);
  }

  const YAML::Node friction = Lookup(root, kFrictionPath);
  if (!friction.IsDefined()) {
    return Invalid(source, absl::StrCat("missing field ", kFrictionPath,
                                        " (\"infinite\" or a coefficient in [0, 10])"));
  }
  double mu = 0;
  if (friction.IsScalar() && friction.Scalar() == "infinite") {
    p.ground.infinite_friction = true;
  } else if (friction.IsScalar() && YAML::convert<double>::decode(friction, mu) &&
             mu >= 0 && mu <= kFrictionMax) {
    p.ground.infinite_friction = false;
    p.ground.friction_coefficient = mu;
  } else {
    return Invalid(Where(source, friction),
                   absl::StrCat(kFrictionPath, " = ", friction.IsScalar() ? friction.Scalar() : "?",
                                " must be \"infinite\" or a Coulomb coefficient in [0, 10]"));
  }

  // Relations between fields.
  const auto& a = p.actuators;
  if (a.min_length_m >= a.max_length_m) {
    return Invalid(Where(source, Lookup(root, "actuators.max_length_m")),
                   "actuators.max_length_m must exceed actuators.min_length_m (m)");
  }
  const double rest = p.RestActuatorLength();
  if (rest < a.min_length_m - 1e-9 || rest > a.max_length_m + 1e-9) {
    std::ostringstream out;
    out << "the rest actuator length lumps.spacing_m + actuators.front_attach_x_m - "
           "actuators.rear_attach_x_m = "
        << rest << " m must lie in [min_length_m, max_length_m] = [" << a.min_length_m << ", "
        << a.max_length_m << "] m";
    return Invalid(Where(source, Lookup(root, "lumps.spacing_m")), out.str());
  }
  if (p.lumps.spacing_m <= p.lumps.size_x_m) {
    return Invalid(Where(source, Lookup(root, "lumps.spacing_m")),
                   "lumps.spacing_m must exceed lumps.size_x_m (m): adjacent boxes overlap");
  }
  return p;
}

}  // namespace

absl::StatusOr<CaterpillarParams> ParseCaterpillarParams(const std::string& text,
                                                         const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(
        absl::StrCat(source, ":", e.mark.line + 1, ": not YAML/JSON: ", e.msg));
  }
  return FromYaml(root, source);
}

absl::StatusOr<CaterpillarParams> LoadCaterpillarParams(const std::string& path) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(absl::StrCat(path, ": cannot open the parameter file"));
  std::stringstream text;
  text << in.rdbuf();
  return ParseCaterpillarParams(text.str(), path);
}

const char* DefaultCaterpillarParamsPath() { return GAITFORGE_CATERPILLAR_PARAMS; }

const CaterpillarParams& DefaultCaterpillarParams() {
  static const CaterpillarParams params = [] {
    auto p = LoadCaterpillarParams(DefaultCaterpillarParamsPath());
    if (!p.ok()) throw std::runtime_error(std::string(p.status().message()));
    return *p;
  }();
  return params;
}

}  // namespace gaitforge::caterpillar
