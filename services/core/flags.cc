#include "services/core/flags.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "absl/strings/str_cat.h"

namespace gaitforge::core {

Flags::Flags(std::string usage, std::string summary)
    : usage_(std::move(usage)), summary_(std::move(summary)) {}

void Flags::Register(Flag flag) {
  // Two flags of one name: the parser would set only the last (a programming error).
  for (const auto& f : flags_)
    if (f.name == flag.name) {
      std::fprintf(stderr, "flag --%s registered twice\n", flag.name.c_str());
      std::abort();
    }
  flags_.push_back(std::move(flag));
}

void Flags::Add(const std::string& name, std::string* value, const std::string& help) {
  Register({name, help, *value, false, [value](const std::string& v) {
                      *value = v;
                      return absl::OkStatus();
                    }});
}

void Flags::Add(const std::string& name, int* value, const std::string& help) {
  Register({name, help, std::to_string(*value), false,
                    [value, name](const std::string& v) {
                      char* end = nullptr;
                      errno = 0;
                      long x = std::strtol(v.c_str(), &end, 10);
                      if (v.empty() || *end || errno || x < INT32_MIN || x > INT32_MAX)
                        return absl::InvalidArgumentError(
                            absl::StrCat("--", name, ": expected an integer, got '", v, "'"));
                      *value = static_cast<int>(x);
                      return absl::OkStatus();
                    }});
}

void Flags::Add(const std::string& name, int64_t* value, const std::string& help) {
  Register({name, help, std::to_string(*value), false,
                    [value, name](const std::string& v) {
                      char* end = nullptr;
                      errno = 0;
                      long long x = std::strtoll(v.c_str(), &end, 10);
                      if (v.empty() || *end || errno)
                        return absl::InvalidArgumentError(
                            absl::StrCat("--", name, ": expected an integer, got '", v, "'"));
                      *value = x;
                      return absl::OkStatus();
                    }});
}

void Flags::Add(const std::string& name, double* value, const std::string& help) {
  Register({name, help, absl::StrCat(*value), false,
                    [value, name](const std::string& v) {
                      char* end = nullptr;
                      double x = std::strtod(v.c_str(), &end);
                      if (v.empty() || *end)
                        return absl::InvalidArgumentError(
                            absl::StrCat("--", name, ": expected a number, got '", v, "'"));
                      *value = x;
                      return absl::OkStatus();
                    }});
}

void Flags::AddBool(const std::string& name, bool* value, const std::string& help) {
  Register({name, help, *value ? "true" : "false", true,
                    [value, name](const std::string& v) {
                      if (v.empty() || v == "true" || v == "1") *value = true;
                      else if (v == "false" || v == "0") *value = false;
                      else
                        return absl::InvalidArgumentError(
                            absl::StrCat("--", name, ": expected true or false, got '", v, "'"));
                      return absl::OkStatus();
                    }});
}

absl::Status Flags::Parse(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      help_ = true;
      continue;
    }
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2), value;
    bool has_value = false;
    if (auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_value = true;
    }
    const Flag* flag = nullptr;
    for (const auto& f : flags_)
      if (f.name == name) flag = &f;
    if (!flag)
      return absl::InvalidArgumentError(
          absl::StrCat("unknown flag --", name, " (see --help)"));
    if (!has_value && !flag->is_bool) {
      if (i + 1 >= argc)
        return absl::InvalidArgumentError(absl::StrCat("--", name, " needs a value"));
      value = argv[++i];
    }
    if (auto s = flag->set(value); !s.ok()) return s;
  }
  return absl::OkStatus();
}

std::string Flags::Help() const {
  std::vector<std::string> all;
  for (const auto& f : flags_) all.push_back(f.name);
  return Help(usage_, summary_, all);
}

std::string Flags::Help(const std::string& usage, const std::string& summary,
                        const std::vector<std::string>& only) const {
  std::string out = absl::StrCat("usage: ", usage, "\n\n", summary, "\n\nflags:\n");
  for (const auto& f : flags_) {
    if (std::find(only.begin(), only.end(), f.name) == only.end()) continue;
    std::string head = absl::StrCat("  --", f.name, f.is_bool ? "" : " VALUE");
    if (head.size() < 28) head.resize(28, ' ');
    else head += "\n" + std::string(28, ' ');
    absl::StrAppend(&out, head, f.help);
    if (!f.default_text.empty()) absl::StrAppend(&out, " (default: ", f.default_text, ")");
    out += "\n";
  }
  absl::StrAppend(&out, "  -h, --help                show this help\n");
  return out;
}

}  // namespace gaitforge::core
