// Locating the mismatch (docs/diagnosis.md step 3): the baseline's residuals sliced by
// clients/python/gaitforge_locate.py, against the model's own spread under the numeric
// variants.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "services/diagnosis/fits.h"
#include "gaitforge/v1/diagnosis.pb.h"

namespace gaitforge::diagnosis {

// The fit's evaluations on files under the numeric variants, already written to
// VariantDir(dir + "/" + stem, i) with the errors given (diagnosis_fits.h, VariantErrors),
// sliced by the locate script into dir/out_json (and figure, when not empty): against the
// variants' spread when every variant ran, else against the noise alone. Returns the
// located JSON, or "{}" with a warning to `note`: locating describes, it does not decide.
using Note = std::function<void(const std::string&)>;
std::string Locate(const std::vector<double>& errors, const std::string& dir,
                   const std::string& stem, const std::string& out_json,
                   const std::string& figure, const Note& note);

// What the located JSONs of the training and the held-out recordings say: whether the
// baseline misses each set beyond the noise and its numeric spread (known only when located
// against the variants), and which recordings show it (their own names, not the downloaded
// HASH16-NAME copies).
struct SpreadReading {
  bool train_known = false, train_beyond = false;
  bool held_known = false, held_beyond = false;
  std::vector<std::string> train_showing, held_showing;
};
SpreadReading ReadSpread(const std::string& located, const std::string& located_held);

// A "none" verdict read against the spread: unexplained when a set shows a mismatch beyond
// it that no catalog effect explained; words saying which of the readings holds ("" when
// the training reading is unknown); experiment: the recording to add when one set cannot
// speak (held-out recordings within the spread cannot confirm; training recordings within
// it do not excite what the held-out ones show), else "".
struct NoneReading {
  bool unexplained = false;
  std::string words, experiment;
};
NoneReading ReadNone(const SpreadReading& r, const std::vector<std::string>& held_files,
                     const std::string& closest);

// A recording's own name: the file name without the HASH16- prefix of a downloaded copy.
std::string OwnName(const std::string& path);

}  // namespace gaitforge::diagnosis
