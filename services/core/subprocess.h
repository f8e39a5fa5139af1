// Child programs a component runs to completion: gaitforge-sim beside this binary, and the
// Python scripts under clients/python (figures, locating a mismatch).
#pragma once

#include <string>
#include <vector>

namespace gaitforge::core {

// Path of a binary next to this one (build/bin or the install prefix), else its bare
// name (found on PATH).
std::string SiblingBinary(const std::string& name);

// Runs argv to completion, capturing its stdout (stderr passes through). Returns the exit
// code (-1 if it could not start or was killed).
int RunCapture(const std::vector<std::string>& argv, std::string* out);

// The Python interpreter that sees Debian's packages ($GAITFORGE_PYTHON, else
// /usr/bin/python3).
std::string Python();

// The path of a script of clients/python: beside $GAITFORGE_PLOT_SCRIPT when set, else in
// the source tree this binary was built from.
std::string PythonScript(const std::string& name);

}  // namespace gaitforge::core
