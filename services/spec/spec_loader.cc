#include "services/spec/spec_loader.h"
#include "services/spec/robot_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::spec {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

class Converter {
 public:
  Converter(std::string source, std::map<std::string, Mark>* marks,
            std::map<std::string, std::string>* clamped)
      : source_(std::move(source)), marks_(marks), clamped_(clamped) {}

  absl::Status Fill(const YAML::Node& node, Message* msg, const std::string& path) {
    const Descriptor* d = msg->GetDescriptor();
    if (!node.IsMap())
      return Error(node, path, absl::StrCat("expected a mapping of ", d->name(), " fields"));
    std::map<std::string, YAML::Mark> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string key = it->first.Scalar();
      const FieldDescriptor* f = d->FindFieldByName(key);
      const std::string fpath = path.empty() ? key : absl::StrCat(path, ".", key);
      if (auto s = Once(it->first, fpath, &seen); !s.ok()) return s;
      if (!f) {
        std::vector<std::string> known;
        for (int i = 0; i < d->field_count(); ++i) known.push_back(d->field(i)->name());
        return Error(it->first, fpath,
                     absl::StrCat("unknown field '", key, "' in ", d->name(), " (known: ",
                                  absl::StrJoin(known, ", "), ")"));
      }
      Record(it->first, fpath);
      if (auto s = SetField(it->second, msg, f, fpath); !s.ok()) return s;
    }
    return absl::OkStatus();
  }

 private:
  // A key written twice in one mapping is an error naming both lines (YAML lets the last
  // one win, silently).
  absl::Status Once(const YAML::Node& key, const std::string& path,
                    std::map<std::string, YAML::Mark>* seen) {
    const auto [it, fresh] = seen->emplace(key.Scalar(), key.Mark());
    if (fresh) return absl::OkStatus();
    const int first = it->second.line + 1, again = key.Mark().line + 1;
    return Error(key, path,
                 first == again
                     ? absl::StrCat("written twice on line ", first, "; keep one")
                     : absl::StrCat("written twice, on lines ", first, " and ", again,
                                    "; keep one"));
  }

  void Record(const YAML::Node& n, const std::string& path) {
    if (marks_) (*marks_)[path] = Mark{n.Mark().line + 1, n.Mark().column + 1};
  }

  absl::Status Error(const YAML::Node& n, const std::string& path, const std::string& what) {
    return absl::InvalidArgumentError(absl::StrCat(source_, ":", n.Mark().line + 1, ":",
                                                   n.Mark().column + 1, ": field '", path,
                                                   "': ", what));
  }

  absl::Status SetField(const YAML::Node& n, Message* msg, const FieldDescriptor* f,
                        const std::string& path) {
    const Reflection* r = msg->GetReflection();
    if (n.IsNull()) return Error(n, path, "has no value");
    if (f->is_map()) {
      if (!n.IsMap()) return Error(n, path, "expected a mapping of names to values");
      const Descriptor* entry = f->message_type();
      std::map<std::string, YAML::Mark> seen;
      for (auto it = n.begin(); it != n.end(); ++it) {
        const std::string key = it->first.Scalar();
        const std::string epath = absl::StrCat(path, ".", key);
        if (auto s = Once(it->first, epath, &seen); !s.ok()) return s;
        Record(it->first, epath);
        Message* e = r->AddMessage(msg, f);
        e->GetReflection()->SetString(e, entry->FindFieldByName("key"), key);
        if (auto s = SetScalar(it->second, e, entry->FindFieldByName("value"), epath, false);
            !s.ok())
          return s;
      }
      return absl::OkStatus();
    }
    if (f->is_repeated()) {
      if (!n.IsSequence()) return Error(n, path, "expected a list");
      for (size_t i = 0; i < n.size(); ++i) {
        const std::string epath = absl::StrCat(path, "[", i, "]");
        Record(n[i], epath);
        if (auto s = SetScalar(n[i], msg, f, epath, true); !s.ok()) return s;
      }
      return absl::OkStatus();
    }
    return SetScalar(n, msg, f, path, false);
  }

  absl::Status SetScalar(const YAML::Node& n, Message* msg, const FieldDescriptor* f,
                         const std::string& path, bool add) {
    const Reflection* r = msg->GetReflection();
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      Message* sub = add ? r->AddMessage(msg, f) : r->MutableMessage(msg, f);
      return Fill(n, sub, path);
    }
    if (!n.IsScalar()) return Error(n, path, "expected a single value");
    const std::string text = n.Scalar();
    switch (f->cpp_type()) {
      case FieldDescriptor::CPPTYPE_STRING:
        add ? r->AddString(msg, f, text) : r->SetString(msg, f, text);
        return absl::OkStatus();
      case FieldDescriptor::CPPTYPE_BOOL: {
        bool v;
        if (!YAML::convert<bool>::decode(n, v)) return Error(n, path, "expected true or false");
        add ? r->AddBool(msg, f, v) : r->SetBool(msg, f, v);
        return absl::OkStatus();
      }
      case FieldDescriptor::CPPTYPE_DOUBLE:
      case FieldDescriptor::CPPTYPE_FLOAT: {
        double v;
        if (!ParseDouble(text, &v))
          return Error(n, path, absl::StrCat("expected a number, got '", text, "'"));
        if (!std::isfinite(v))
          return Error(n, path, absl::StrCat("expected a finite number, got '", text, "'"));
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE)
          add ? r->AddDouble(msg, f, v) : r->SetDouble(msg, f, v);
        else
          add ? r->AddFloat(msg, f, static_cast<float>(v))
              : r->SetFloat(msg, f, static_cast<float>(v));
        return absl::OkStatus();
      }
      case FieldDescriptor::CPPTYPE_INT32:
      case FieldDescriptor::CPPTYPE_INT64: {
        long long v;
        const bool is32 = f->cpp_type() == FieldDescriptor::CPPTYPE_INT32;
        const long long lo = is32 ? std::numeric_limits<int32_t>::min() : LLONG_MIN;
        const long long hi = is32 ? std::numeric_limits<int32_t>::max() : LLONG_MAX;
        const IntText parsed = ParseInt(text, &v);
        if (parsed == IntText::kNotInteger || (!clamped_ && (parsed == IntText::kOverflow ||
                                                             v < lo || v > hi)))
          return Error(n, path,
                       absl::StrCat("expected an integer in [", lo, ", ", hi, "], got '", text,
                                    "'"));
        if (parsed == IntText::kOverflow || v < lo || v > hi) {
          // Validation names the field's own range; the type's would only mislead.
          v = std::clamp(v, lo, hi);
          (*clamped_)[path] = text;
        }
        if (is32)
          add ? r->AddInt32(msg, f, static_cast<int32_t>(v))
              : r->SetInt32(msg, f, static_cast<int32_t>(v));
        else
          add ? r->AddInt64(msg, f, v) : r->SetInt64(msg, f, v);
        return absl::OkStatus();
      }
      case FieldDescriptor::CPPTYPE_UINT32:
      case FieldDescriptor::CPPTYPE_UINT64: {
        unsigned long long v;
        const bool is32 = f->cpp_type() == FieldDescriptor::CPPTYPE_UINT32;
        const unsigned long long hi = is32 ? std::numeric_limits<uint32_t>::max() : ULLONG_MAX;
        if (!ParseUint(text, &v) || v > hi)
          return Error(n, path,
                       absl::StrCat("expected an integer in [0, ", hi, "], got '", text, "'"));
        if (is32)
          add ? r->AddUInt32(msg, f, static_cast<uint32_t>(v))
              : r->SetUInt32(msg, f, static_cast<uint32_t>(v));
        else
          add ? r->AddUInt64(msg, f, v) : r->SetUInt64(msg, f, v);
        return absl::OkStatus();
      }
      case FieldDescriptor::CPPTYPE_ENUM: {
        const auto* value = f->enum_type()->FindValueByName(text);
        if (!value) {
          std::vector<std::string> names;
          for (int i = 0; i < f->enum_type()->value_count(); ++i)
            names.push_back(f->enum_type()->value(i)->name());
          return Error(n, path, absl::StrCat("expected one of ", absl::StrJoin(names, ", ")));
        }
        add ? r->AddEnumValue(msg, f, value->number()) : r->SetEnumValue(msg, f, value->number());
        return absl::OkStatus();
      }
      default:
        return Error(n, path, "unsupported field type");
    }
  }

  static bool ParseDouble(const std::string& s, double* v) {
    if (s == ".nan" || s == ".NaN" || s == ".NAN") {
      *v = std::numeric_limits<double>::quiet_NaN();
      return true;
    }
    if (s == ".inf" || s == "-.inf" || s == "+.inf") {
      *v = s[0] == '-' ? -INFINITY : INFINITY;
      return true;
    }
    if (s.empty()) return false;
    char* end = nullptr;
    errno = 0;
    *v = std::strtod(s.c_str(), &end);
    return end && *end == '\0' && errno != ERANGE;
  }
  enum class IntText { kInteger, kOverflow, kNotInteger };
  // kOverflow: an integer beyond long long; *v is LLONG_MIN or LLONG_MAX.
  static IntText ParseInt(const std::string& s, long long* v) {
    if (s.empty()) return IntText::kNotInteger;
    char* end = nullptr;
    errno = 0;
    *v = std::strtoll(s.c_str(), &end, 10);
    if (!end || *end != '\0') return IntText::kNotInteger;
    return errno == ERANGE ? IntText::kOverflow : IntText::kInteger;
  }
  static bool ParseUint(const std::string& s, unsigned long long* v) {
    if (s.empty() || s[0] == '-') return false;
    char* end = nullptr;
    errno = 0;
    *v = std::strtoull(s.c_str(), &end, 10);
    return end && *end == '\0' && errno != ERANGE;
  }

  std::string source_;
  std::map<std::string, Mark>* marks_;
  std::map<std::string, std::string>* clamped_;
};

}  // namespace

absl::Status ParseMessage(const std::string& text, const std::string& source,
                          google::protobuf::Message* message, std::map<std::string, Mark>* marks,
                          std::map<std::string, std::string>* clamped) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ":",
                                                   e.mark.column + 1, ": not valid YAML/JSON: ",
                                                   e.msg));
  }
  if (!root.IsDefined() || root.IsNull())
    return absl::InvalidArgumentError(absl::StrCat(source, ": the file is empty"));
  try {
    return Converter(source, marks, clamped).Fill(root, message, "");
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ":",
                                                   e.mark.column + 1, ": ", e.msg));
  }
}

absl::StatusOr<LoadedSpec> ParseSpec(const std::string& text, const std::string& source) {
  LoadedSpec out;
  out.source = source;
  if (auto s = ParseMessage(text, source, &out.spec, &out.marks, &out.clamped); !s.ok())
    return s;
  // Written but empty: not "the objective's default space", which is what leaving it out
  // means.
  if (auto it = out.marks.find("bounds"); it != out.marks.end() && out.spec.bounds_size() == 0)
    return absl::InvalidArgumentError(absl::StrCat(
        source, ":", it->second.line, ":", it->second.column,
        ": field 'bounds' is an empty list; give at least one gene, or leave 'bounds' out for "
        "the objective's default space"));
  return out;
}

absl::StatusOr<LoadedSpec> LoadSpecFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return absl::InvalidArgumentError(
        absl::StrCat("'", path, "' is a directory; give a spec file (.yaml or .json)"));
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot open spec file '", path, "'"));
  std::stringstream ss;
  ss << in.rdbuf();
  auto loaded = ParseSpec(ss.str(), path);
  if (!loaded.ok()) return loaded;
  if (auto s = EmbedRobotFile(*loaded); !s.ok()) return s;
  return loaded;
}

}  // namespace gaitforge::spec
