#pragma once
// A number in a descriptor's structure sections: a constant, a parameter's name, or a small
// linear expression of them ("0.5*body.height_m", "body.length_m + 0.002", "-hip.x_m"), so
// that a body's size or a joint's anchor follows the parameters a calibration changes.
#include <functional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace gaitforge::robots {

struct Expr {
  double constant = 0;
  struct Term {
    double coef = 1;
    std::string name;  // a parameter
  };
  std::vector<Term> terms;
  std::string text;  // as written

  double Eval(const std::function<double(const std::string&)>& value_of) const;
};

// Parses "[-]A [* NAME] (+|- ...)" where A is a number; a term may be NUMBER, NAME,
// NUMBER*NAME or NAME*NUMBER. The error says what was expected.
absl::StatusOr<Expr> ParseExpr(const std::string& text);

}  // namespace gaitforge::robots
