// Writing JSON by hand where a report is assembled piece by piece: quoted strings and
// numbers (non-finite numbers become null).
#pragma once

#include <string>
#include <vector>

namespace gaitforge::core {

std::string JsonQuote(const std::string& s);                    // "..." with escapes
std::string JsonNum(double x);                                   // %.6g, or null
std::string JsonNumList(const std::vector<double>& v);           // [1, 2, null]
std::string JsonStringList(const std::vector<std::string>& v);   // ["a", "b"]

}  // namespace gaitforge::core
