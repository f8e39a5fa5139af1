// The JSON sidecar of a recording: a strict JSON syntax check (yaml-cpp accepts a superset
// of JSON: trailing commas, single quotes, text after the object), then the tree from
// yaml-cpp, whose nodes carry line and column marks for the messages.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "services/recording/recording_internal.h"

namespace gaitforge::recording::internal {
namespace {

constexpr int kMaxJsonDepth = 32;

class JsonChecker {
 public:
  JsonChecker(std::string_view text, const std::string& name) : s_(text), name_(name) {}

  absl::Status Check() {
    SkipSpace();
    if (AtEnd()) return Error("expected a JSON object ('{'), got an empty file");
    if (Peek() != '{') return Error(absl::StrCat("expected a JSON object ('{'), got ", Got()));
    if (auto st = Value(0); !st.ok()) return st;
    SkipSpace();
    if (!AtEnd()) return Error(absl::StrCat("unexpected ", Got(), " after the JSON object"));
    return absl::OkStatus();
  }

 private:
  bool AtEnd() const { return i_ >= s_.size(); }
  char Peek() const { return s_[i_]; }
  void Advance() {
    if (s_[i_] == '\n') {
      ++line_;
      col_ = 1;
    } else {
      ++col_;
    }
    ++i_;
  }
  void SkipSpace() {
    while (!AtEnd() && (Peek() == ' ' || Peek() == '\t' || Peek() == '\n' || Peek() == '\r'))
      Advance();
  }
  std::string Got() const {
    if (AtEnd()) return "the end of the file";
    const unsigned char c = static_cast<unsigned char>(Peek());
    if (c >= 0x80 || c < 0x20 || c == 0x7f) return absl::StrFormat("the byte 0x%02x", c);
    return absl::StrCat("'", std::string(s_.substr(i_, 1)), "'");
  }
  absl::Status Error(const std::string& what) const {
    return absl::InvalidArgumentError(
        absl::StrCat(name_, ":", line_, ":", col_, ": not valid JSON: ", what));
  }

  absl::Status Value(int depth) {
    if (AtEnd()) return Error("expected a value, got the end of the file");
    switch (Peek()) {
      case '{':
        return Object(depth + 1);
      case '[':
        return Array(depth + 1);
      case '"':
        return String();
      case 't':
        return Literal("true");
      case 'f':
        return Literal("false");
      case 'n':
        return Literal("null");
      default:
        if (Peek() == '-' || (Peek() >= '0' && Peek() <= '9')) return Number();
        return Error(absl::StrCat("expected a value, got ", Got()));
    }
  }

  absl::Status Object(int depth) {
    if (depth > kMaxJsonDepth) return Error("nested too deeply");
    Advance();  // '{'
    SkipSpace();
    if (!AtEnd() && Peek() == '}') {
      Advance();
      return absl::OkStatus();
    }
    for (;;) {
      SkipSpace();
      if (AtEnd() || Peek() != '"')
        return Error(absl::StrCat("expected a member name in double quotes, got ", Got()));
      if (auto st = String(); !st.ok()) return st;
      SkipSpace();
      if (AtEnd() || Peek() != ':')
        return Error(absl::StrCat("expected ':' after the member name, got ", Got()));
      Advance();
      SkipSpace();
      if (auto st = Value(depth); !st.ok()) return st;
      SkipSpace();
      if (!AtEnd() && Peek() == ',') {
        Advance();
        continue;
      }
      if (!AtEnd() && Peek() == '}') {
        Advance();
        return absl::OkStatus();
      }
      return Error(absl::StrCat("expected ',' or '}' after an object member, got ", Got()));
    }
  }

  absl::Status Array(int depth) {
    if (depth > kMaxJsonDepth) return Error("nested too deeply");
    Advance();  // '['
    SkipSpace();
    if (!AtEnd() && Peek() == ']') {
      Advance();
      return absl::OkStatus();
    }
    for (;;) {
      SkipSpace();
      if (auto st = Value(depth); !st.ok()) return st;
      SkipSpace();
      if (!AtEnd() && Peek() == ',') {
        Advance();
        continue;
      }
      if (!AtEnd() && Peek() == ']') {
        Advance();
        return absl::OkStatus();
      }
      return Error(absl::StrCat("expected ',' or ']' after an array element, got ", Got()));
    }
  }

  absl::Status String() {
    Advance();  // '"'
    while (!AtEnd()) {
      const unsigned char c = static_cast<unsigned char>(Peek());
      if (c == '"') {
        Advance();
        return absl::OkStatus();
      }
      if (c < 0x20) return Error("control character in a string (write it as an escape)");
      if (c == '\\') {
        Advance();
        if (AtEnd()) break;
        const char e = Peek();
        if (e == 'u') {
          Advance();
          for (int k = 0; k < 4; ++k) {
            if (AtEnd() || !std::isxdigit(static_cast<unsigned char>(Peek())))
              return Error(absl::StrCat("expected 4 hex digits after \\u, got ", Got()));
            Advance();
          }
          continue;
        }
        if (std::string_view("\"\\/bfnrt").find(e) == std::string_view::npos)
          return Error(absl::StrCat("unknown escape \\", Quote(std::string_view(&e, 1))));
      }
      Advance();
    }
    return Error("unterminated string");
  }

  absl::Status Number() {
    auto digits = [&] {
      int n = 0;
      while (!AtEnd() && Peek() >= '0' && Peek() <= '9') {
        Advance();
        ++n;
      }
      return n;
    };
    if (Peek() == '-') Advance();
    if (AtEnd() || !(Peek() >= '0' && Peek() <= '9'))
      return Error(absl::StrCat("expected a digit, got ", Got()));
    if (Peek() == '0') {
      Advance();
    } else {
      digits();
    }
    if (!AtEnd() && Peek() == '.') {
      Advance();
      if (digits() == 0) return Error(absl::StrCat("expected a digit after '.', got ", Got()));
    }
    if (!AtEnd() && (Peek() == 'e' || Peek() == 'E')) {
      Advance();
      if (!AtEnd() && (Peek() == '+' || Peek() == '-')) Advance();
      if (digits() == 0)
        return Error(absl::StrCat("expected a digit in the exponent, got ", Got()));
    }
    if (!AtEnd() && (std::isalnum(static_cast<unsigned char>(Peek())) || Peek() == '.'))
      return Error(absl::StrCat("unexpected ", Got(), " in a number"));
    return absl::OkStatus();
  }

  absl::Status Literal(std::string_view word) {
    if (s_.substr(i_, word.size()) != word) {
      return Error(absl::StrCat("expected a value, got ", Got()));
    }
    for (size_t k = 0; k < word.size(); ++k) Advance();
    if (!AtEnd() && std::isalnum(static_cast<unsigned char>(Peek())))
      return Error(absl::StrCat("unexpected ", Got(), " after '", std::string(word), "'"));
    return absl::OkStatus();
  }

  std::string_view s_;
  const std::string& name_;
  const RobotInfo* given_;
  size_t i_ = 0;
  int line_ = 1, col_ = 1;
};

// Walks the yaml-cpp tree of a syntactically valid JSON sidecar.
class SidecarReader {
 public:
  SidecarReader(const std::string& name, const RobotInfo* given) : name_(name), given_(given) {}

  absl::StatusOr<Sidecar> Read(const YAML::Node& root) {
    Sidecar out;
    std::map<std::string, YAML::Node> top;
    if (auto st = Members(
            root, "", {"robot", "parameters", "overrides", "command", "source", "note", "channels"},
            &top);
        !st.ok())
      return st;

    // robot
    auto robot = Require(root, top, "", "robot");
    if (!robot.ok()) return robot.status();
    if (auto st = String(*robot, "robot", &out.meta.robot); !st.ok()) return st;
    out.robot = given_ && given_->name == out.meta.robot ? given_ : FindRobot(out.meta.robot);
    if (!out.robot)
      return Error(*robot, absl::StrCat("unknown robot '", Quote(out.meta.robot),
                                        "' (built in: ", KnownRobots(),
                                        given_ ? absl::StrCat("; the descriptor given: ", given_->name)
                                               : "; another robot's recording needs its descriptor",
                                        ")"));

    if (auto st = OptionalString(top, "parameters", &out.meta.parameters); !st.ok()) return st;
    if (auto st = OptionalString(top, "source", &out.meta.source); !st.ok()) return st;
    if (auto st = OptionalString(top, "note", &out.meta.note); !st.ok()) return st;

    // overrides
    if (auto it = top.find("overrides"); it != top.end() && !it->second.IsNull()) {
      if (!it->second.IsMap()) return Expected(it->second, "overrides", "an object");
      std::map<std::string, YAML::Node> entries;
      if (auto st = Members(it->second, "overrides", {}, &entries); !st.ok()) return st;
      for (const auto& [key, value] : entries) {
        double v;
        if (auto st = Number(value, absl::StrCat("overrides.", key), &v); !st.ok()) return st;
        out.meta.overrides[key] = v;
      }
    }

    // command
    auto command = Require(root, top, "", "command");
    if (!command.ok()) return command.status();
    if (!command->IsMap()) return Expected(*command, "command", "an object");
    std::map<std::string, YAML::Node> cmd;
    if (auto st = Members(*command, "command", {"kind", "genes"}, &cmd); !st.ok()) return st;
    auto kind = Require(*command, cmd, "command", "kind");
    if (!kind.ok()) return kind.status();
    if (auto st = String(*kind, "command.kind", &out.meta.command_kind); !st.ok()) return st;
    out.command_mark = {kind->Mark().line + 1, kind->Mark().column + 1};
    if (out.meta.command_kind == "playback" || out.meta.command_kind == "path") {
      // A playback's actuators take the recording's own input columns (ParseRecording checks
      // them); a path is where a tracking controller should take a marker.
      if (cmd.count("genes"))
        return Error(cmd["genes"], absl::StrCat("key 'command.genes': a ", out.meta.command_kind,
                                                " has no genes (",
                                                out.meta.command_kind == "path"
                                                    ? "it is a marker's reference positions"
                                                    : "its actuators follow the recording's "
                                                      "input columns",
                                                ")"));
    } else if (out.meta.command_kind != "gait") {
      return Error(*kind, absl::StrCat("key 'command.kind': unknown command kind '",
                                       Quote(out.meta.command_kind),
                                       "' (known: gait, playback, path)"));
    } else if (auto st = ParseGenes(*command, cmd, *out.robot, out.meta); !st.ok()) {
      return st;
    }

    // channels
    if (auto it = top.find("channels"); it != top.end() && !it->second.IsNull()) {
      if (!it->second.IsMap()) return Expected(it->second, "channels", "an object");
      std::map<std::string, YAML::Node> chans;
      std::map<std::string, YAML::Node> chan_keys;
      if (auto st = Members(it->second, "channels", {}, &chans, &chan_keys); !st.ok()) return st;
      for (const auto& [ch, spec] : chans) {
        const std::string path = absl::StrCat("channels.", ch);
        const auto& known = out.robot->channels;
        if (std::find(known.begin(), known.end(), ch) == known.end())
          return Error(chan_keys[ch],
                       absl::StrCat("key '", Quote(path), "': unknown channel '", Quote(ch),
                                    "' for robot '", out.robot->name, "'"));
        if (!spec.IsMap()) return Expected(spec, path, "an object such as {\"unit\": \"m\"}");
        std::map<std::string, YAML::Node> fields;
        if (auto st = Members(spec, path, {"unit"}, &fields); !st.ok()) return st;
        auto unit_node = Require(spec, fields, path, "unit");
        if (!unit_node.ok()) return unit_node.status();
        std::string unit;
        if (auto st = String(*unit_node, path + ".unit", &unit); !st.ok()) return st;
        if (unit != out.robot->units.at(ch))
          return Error(*unit_node,
                       absl::StrCat("key '", Quote(path), ".unit': channel '", ch, "' is in ",
                                    out.robot->units.at(ch), ", not '", Quote(unit), "'"));
        out.meta.channel_units[ch] = unit;
        out.channel_marks[ch] = {chan_keys[ch].Mark().line + 1, chan_keys[ch].Mark().column + 1};
      }
    }
    return out;
  }

 private:
  // command.genes of a "gait" command: as many numbers as the robot's controller takes.
  absl::Status ParseGenes(const YAML::Node& command, const std::map<std::string, YAML::Node>& cmd,
                          const RobotInfo& robot, RecordingMeta& meta) const {
    auto genes = Require(command, cmd, "command", "genes");
    if (!genes.ok()) return genes.status();
    if (!genes->IsSequence()) return Expected(*genes, "command.genes", "an array of numbers");
    for (size_t i = 0; i < genes->size(); ++i) {
      double v;
      if (auto st = Number((*genes)[i], absl::StrCat("command.genes[", i, "]"), &v); !st.ok())
        return st;
      meta.genes.push_back(v);
    }
    if (static_cast<int>(meta.genes.size()) != robot.gene_count)
      return Error(*genes, absl::StrCat("key 'command.genes': the ", robot.name, " takes ",
                                        robot.gene_count, " genes (", robot.gene_names, "), got ",
                                        meta.genes.size()));
    return absl::OkStatus();
  }

  absl::Status Error(const YAML::Node& n, const std::string& what) const {
    return absl::InvalidArgumentError(
        absl::StrCat(name_, ":", n.Mark().line + 1, ":", n.Mark().column + 1, ": ", what));
  }

  static std::string Describe(const YAML::Node& n) {
    if (n.IsNull()) return "null";
    if (n.IsSequence()) return "an array";
    if (n.IsMap()) return "an object";
    if (n.Tag() == "!") return absl::StrCat("the string \"", Quote(n.Scalar()), "\"");
    if (n.Scalar() == "true" || n.Scalar() == "false") return n.Scalar();
    return absl::StrCat("the number ", Quote(n.Scalar()));
  }

  absl::Status Expected(const YAML::Node& n, const std::string& path,
                        const std::string& what) const {
    return Error(n,
                 absl::StrCat("key '", Quote(path), "': expected ", what, ", got ", Describe(n)));
  }

  // The members of object `n` by name. Duplicates and, when `allowed` is not empty, names
  // outside it are errors.
  absl::Status Members(const YAML::Node& n, const std::string& path,
                       const std::vector<std::string>& allowed,
                       std::map<std::string, YAML::Node>* out,
                       std::map<std::string, YAML::Node>* keys = nullptr) const {
    std::map<std::string, int> first_line;
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string key = it->first.Scalar();
      const std::string full = path.empty() ? key : absl::StrCat(path, ".", key);
      if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        return Error(it->first, absl::StrCat("unknown key '", Quote(full), "' (known",
                                             path.empty() ? "" : absl::StrCat(" in ", path), ": ",
                                             absl::StrJoin(allowed, ", "), ")"));
      if (auto f = first_line.find(key); f != first_line.end())
        return Error(it->first, absl::StrCat("duplicate key '", Quote(full), "' (first at line ",
                                             f->second, ")"));
      first_line[key] = it->first.Mark().line + 1;
      (*out)[key] = it->second;
      if (keys) (*keys)[key] = it->first;
    }
    return absl::OkStatus();
  }

  absl::StatusOr<YAML::Node> Require(const YAML::Node& object,
                                     const std::map<std::string, YAML::Node>& members,
                                     const std::string& path, const std::string& key) const {
    auto it = members.find(key);
    if (it == members.end())
      return Error(object, absl::StrCat("missing required key '",
                                        path.empty() ? key : absl::StrCat(path, ".", key), "'"));
    return it->second;
  }

  absl::Status String(const YAML::Node& n, const std::string& path, std::string* out) const {
    if (!n.IsScalar() || n.Tag() != "!") return Expected(n, path, "a string");
    *out = n.Scalar();
    return absl::OkStatus();
  }

  absl::Status OptionalString(const std::map<std::string, YAML::Node>& top, const std::string& key,
                              std::string* out) const {
    auto it = top.find(key);
    if (it == top.end() || it->second.IsNull()) return absl::OkStatus();
    return String(it->second, key, out);
  }

  absl::Status Number(const YAML::Node& n, const std::string& path, double* out) const {
    if (!n.IsScalar() || n.Tag() == "!" || n.Scalar() == "true" || n.Scalar() == "false")
      return Expected(n, path, "a number");
    if (!ParseFiniteDouble(n.Scalar(), out))
      return Error(n, absl::StrCat("key '", Quote(path), "': expected a finite number, got ",
                                   Quote(n.Scalar())));
    return absl::OkStatus();
  }

  const std::string& name_;
  const RobotInfo* given_;
};

}  // namespace

absl::Status CheckJsonSyntax(std::string_view text, const std::string& name) {
  return JsonChecker(text, name).Check();
}

absl::StatusOr<Sidecar> ParseSidecar(std::string_view text, const std::string& name,
                                     const RobotInfo* robot) {
  text = StripBom(text);
  if (auto st = CheckJsonSyntax(text, name); !st.ok()) return st;
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    // Valid JSON that yaml-cpp still refuses (rare: e.g. some escapes).
    return absl::InvalidArgumentError(
        absl::StrCat(name, ":", e.mark.line + 1, ":", e.mark.column + 1, ": ", e.msg));
  }
  if (!root.IsMap())
    return absl::InvalidArgumentError(absl::StrCat(name, ":1:1: expected a JSON object"));
  try {
    return SidecarReader(name, robot).Read(root);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(name, ": ", e.what()));
  }
}

}  // namespace gaitforge::recording::internal
