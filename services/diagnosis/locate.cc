// Locating the mismatch: see diagnosis_locate.h.
#include "services/diagnosis/locate.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "services/core/subprocess.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"

namespace gaitforge::diagnosis {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str().empty() ? "{}" : text.str();
}

}  // namespace

std::string Locate(const std::vector<double>& errors, const std::string& dir,
                   const std::string& stem, const std::string& out_json,
                   const std::string& figure, const Note& note) {
  const std::string main = VariantDir(dir + "/" + stem, 0);
  if (errors.empty() || !std::isfinite(errors[0])) {
    note(absl::StrCat("warning: the model as fitted failed on ", main,
                      "'s recordings; the report has no 'where it showed' for them"));
    return "{}";
  }
  std::vector<std::string> argv = {
      core::Python(), core::PythonScript("gaitforge_locate.py"),
      "--eval", main + "/eval.json", "--out", dir + "/" + out_json};
  if (!figure.empty()) argv.insert(argv.end(), {"--figure", dir + "/" + figure});
  // The model's own spread on the same recordings: the fit under the other numeric
  // variants. A drift or shape the variants already disagree on is chaos, not a mismatch.
  std::vector<std::string> spread;
  for (size_t i = 1; i < errors.size() && std::isfinite(errors[i]); ++i)
    spread.push_back(VariantDir(dir + "/" + stem, i) + "/eval.json");
  std::string ignored;
  if (spread.size() + 1 == errors.size() && spread.size() > 0) {
    std::vector<std::string> with = argv;
    with.insert(with.end(), {"--variants", absl::StrJoin(spread, ",")});
    if (core::RunCapture(with, &ignored) == 0) return ReadAll(dir + "/" + out_json);
    note(absl::StrCat("warning: locating against the numeric variants failed on ", main,
                      "; locating against the noise alone"));
  }
  // A variant failed (a fit that diverges at one timestep): locate against the noise alone.
  if (const int code = core::RunCapture(argv, &ignored); code != 0) {
    note(absl::StrCat("warning: locating the mismatch failed (gaitforge_locate.py exit ", code,
                      " on ", main,
                      "/eval.json); the report has no 'where it showed' for those recordings"));
    return "{}";
  }
  return ReadAll(dir + "/" + out_json);
}

std::string OwnName(const std::string& path) {
  const std::string f = std::filesystem::path(path).filename();
  bool hashed = f.size() > 17 && f[16] == '-';
  for (size_t i = 0; hashed && i < 16; ++i)
    hashed = std::isxdigit(static_cast<unsigned char>(f[i])) != 0;
  return hashed ? f.substr(17) : f;
}

SpreadReading ReadSpread(const std::string& located, const std::string& located_held) {
  SpreadReading r;
  auto read = [](const std::string& json, bool* known, bool* beyond,
                 std::vector<std::string>* showing) {
    google::protobuf::Struct w;
    if (!google::protobuf::util::JsonStringToMessage(json, &w).ok()) return;
    auto it = w.fields().find("beyond_spread");
    if (it == w.fields().end() || it->second.kind_case() != google::protobuf::Value::kBoolValue)
      return;
    *known = true;
    *beyond = it->second.bool_value();
    auto names = w.fields().find("beyond_recordings");
    if (names != w.fields().end())
      for (const auto& v : names->second.list_value().values())
        showing->push_back(OwnName(v.string_value()));
  };
  read(located, &r.train_known, &r.train_beyond, &r.train_showing);
  read(located_held, &r.held_known, &r.held_beyond, &r.held_showing);
  return r;
}

NoneReading ReadNone(const SpreadReading& r, const std::vector<std::string>& held_files,
                     const std::string& closest) {
  NoneReading n;
  if (!r.train_known) return n;
  const std::string spread = "the noise and its own numeric spread";
  const std::string lacking =
      ": what is missing is not a catalog effect the held-out recordings confirm "
      "(docs/effects.md); it may be physics the catalog does not hold, or a difference in the "
      "model's structure" +
      (closest.empty() ? std::string() : " (closest held out: " + closest + ")");
  std::vector<std::string> held_names;
  for (const auto& f : held_files) held_names.push_back(OwnName(f));
  const std::string held = absl::StrJoin(held_names, ", ");
  if (r.train_beyond) {
    n.unexplained = true;
    const bool both = r.held_known && r.held_beyond;
    n.words = "yet the calibrated model still misses the training " +
              std::string(both ? "and held-out " : "") + "recordings beyond " + spread +
              " (where it showed, below)" + lacking;
    if (r.held_known && !r.held_beyond)
      n.experiment = "The held-out recordings (" + held +
                     ") match the baseline within the noise and its numeric spread, so they "
                     "cannot confirm a cause the training recordings show; hold out a recording "
                     "of a gait where the mismatch shows (as " +
                     absl::StrJoin(r.train_showing, ", ") +
                     (r.train_showing.size() > 1 ? " do" : " does") + "), or a longer one.";
  } else if (r.held_known && r.held_beyond) {
    n.unexplained = true;
    n.words = "the calibrated model matches the training recordings within " + spread +
              " but misses the held-out recordings beyond it" + lacking;
    n.experiment = "The training recordings match the baseline within the noise and its "
                   "numeric spread while the held-out ones (" +
                   absl::StrJoin(r.held_showing, ", ") +
                   ") do not: the training gaits do not excite what is missing; train on a gait "
                   "like the held-out one, or swap a training and a held-out recording.";
  } else {
    n.words = "the calibrated model matches the training " +
              std::string(r.held_known ? "and held-out " : "") + "recordings within " + spread;
  }
  return n;
}

}  // namespace gaitforge::diagnosis
