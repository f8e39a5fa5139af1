#include "services/recording/recording.h"

#include <openssl/evp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "services/recording/recording_internal.h"

namespace gaitforge::recording {

namespace internal {

RobotInfo InfoOf(const robots::RobotDescriptor& d) {
  RobotInfo info;
  info.name = d.name;
  info.channels = d.Channels();
  for (const auto& c : info.channels) info.units[c] = UnitOf(c);
  for (const auto& a : d.actuators) {
    info.inputs.push_back(a.InputChannel());
    info.units[a.InputChannel()] = a.InputUnit();
  }
  info.channels.insert(info.channels.end(), info.inputs.begin(), info.inputs.end());
  info.gene_count = static_cast<int>(d.controller.genes.size());
  std::vector<std::string> genes;
  for (const auto& g : d.controller.genes) genes.push_back(g.name);
  info.gene_names = absl::StrJoin(genes, " ");
  info.markers = d.MarkerCount();
  info.marker_pitch_m = d.MarkerSpacing();
  return info;
}

// The built-in robots (robots/registry.h), whose sensors give the channels and whose
// controller gives the genes of a "gait" command.
const RobotInfo* FindRobot(std::string_view name) {
  static const std::vector<RobotInfo>* robots = [] {
    auto* v = new std::vector<RobotInfo>;
    for (const std::string& n : robots::RobotNames()) v->push_back(InfoOf(robots::Robot(n)));
    return v;
  }();
  for (const auto& r : *robots)
    if (r.name == name) return &r;
  return nullptr;
}

std::string KnownRobots() { return absl::StrJoin(robots::RobotNames(), ", "); }

std::string UnitOf(std::string_view channel) {
  const size_t dot = channel.rfind('.');
  const std::string_view field = dot == std::string_view::npos ? "" : channel.substr(dot + 1);
  return field == "angle" || field == "angle1" || field == "angle2" ? "rad" : "m";
}

std::string Quote(std::string_view s) {
  constexpr size_t kMax = 40;
  bool cut = false;
  if (s.size() > kMax) {
    size_t n = kMax;
    // Not inside a UTF-8 sequence.
    while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
    s = s.substr(0, n);
    cut = true;
  }
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c >= 0x80) {
      // Valid UTF-8 sequences stay as they are; other bytes become \xNN.
      const size_t len = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
      bool valid = len > 0 && i + len <= s.size();
      for (size_t k = 1; valid && k < len; ++k)
        valid = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
      if (valid) {
        out.append(s.substr(i, len));
        i += len - 1;
      } else {
        out += absl::StrFormat("\\x%02x", c);
      }
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      out += absl::StrFormat("\\x%02x", c);
    } else {
      out += ch;
    }
  }
  if (cut) out += "...";
  return out;
}

std::string_view StripBom(std::string_view s) {
  if (s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
  return s;
}

bool ParseFiniteDouble(std::string_view s, double* out) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') {
    ++b;
    if (b != e && *b == '-') return false;  // "+-1"
  }
  if (b == e) return false;
  // Only digits, '.', signs and exponents: from_chars would also take "inf" and "nan".
  const char first = *b == '-' && b + 1 != e ? b[1] : *b;
  if (!(first == '.' || (first >= '0' && first <= '9'))) return false;
  double v = 0;
  auto [ptr, ec] = std::from_chars(b, e, v, std::chars_format::general);
  if (ptr != e) return false;
  if (ec == std::errc::result_out_of_range) {
    // Overflow, or a value below the smallest double: strtod tells them apart.
    const std::string copy(b, e);
    v = std::strtod(copy.c_str(), nullptr);
    if (!std::isfinite(v)) return false;
  } else if (ec != std::errc()) {
    return false;
  }
  if (!std::isfinite(v)) return false;
  *out = v;
  return true;
}

}  // namespace internal

namespace {

using internal::Quote;

absl::Status Err(const std::string& file, int line, int col, const std::string& what) {
  if (line <= 0) return absl::InvalidArgumentError(absl::StrCat(file, ": ", what));
  if (col <= 0) return absl::InvalidArgumentError(absl::StrCat(file, ":", line, ": ", what));
  return absl::InvalidArgumentError(absl::StrCat(file, ":", line, ":", col, ": ", what));
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool IsBlank(std::string_view s) {
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; });
}

// Iterates over the lines of a buffer: LF or CRLF, the last one with or without a newline.
class Lines {
 public:
  explicit Lines(std::string_view s) : s_(s) {}
  // The next line without its line ending; false at the end.
  bool Next(std::string_view* line) {
    if (pos_ >= s_.size()) return false;
    const char* b = s_.data() + pos_;
    const void* nl = std::memchr(b, '\n', s_.size() - pos_);
    const size_t end =
        nl ? static_cast<size_t>(static_cast<const char*>(nl) - s_.data()) : s_.size();
    *line = s_.substr(pos_, end - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  int number() const { return number_; }  // 1-based number of the last line returned
  std::string_view rest() const { return pos_ >= s_.size() ? std::string_view() : s_.substr(pos_); }

 private:
  std::string_view s_;
  size_t pos_ = 0;
  int number_ = 0;
};

std::string Num(double v) { return absl::StrFormat("%.6g", v); }

absl::Status ParseHeader(std::string_view header, const std::string& name,
                         const internal::RobotInfo& robot, std::vector<std::string>* channels) {
  std::vector<std::string_view> cols;
  for (size_t b = 0;;) {
    const size_t comma = header.find(',', b);
    cols.push_back(Trim(header.substr(b, comma == std::string_view::npos ? comma : comma - b)));
    if (comma == std::string_view::npos) break;
    b = comma + 1;
  }
  for (size_t c = 0; c < cols.size(); ++c)
    if (cols[c].empty())
      return Err(name, 1, static_cast<int>(c) + 1,
                 cols.size() == 1 ? "empty header row; expected 't' and the channel names"
                                  : "empty column name");
  if (cols[0] != "t") {
    auto t_at = std::find(cols.begin(), cols.end(), std::string_view("t"));
    std::string what =
        absl::StrCat("the first column must be 't' (time in s), got '", Quote(cols[0]), "'");
    if (t_at != cols.end())
      absl::StrAppend(&what, "; 't' is column ", t_at - cols.begin() + 1);
    else
      absl::StrAppend(&what, "; there is no 't' column");
    if (cols.size() == 1 && (cols[0].find(';') != std::string_view::npos ||
                             cols[0].find('\t') != std::string_view::npos))
      absl::StrAppend(&what, " (columns are separated by ',')");
    return Err(name, 1, 1, what);
  }
  if (cols.size() == 1) return Err(name, 1, 0, "no channel columns after 't'");
  for (size_t c = 1; c < cols.size(); ++c) {
    for (size_t d = 0; d < c; ++d)
      if (cols[d] == cols[c])
        return Err(
            name, 1, static_cast<int>(c) + 1,
            absl::StrCat("duplicate column '", Quote(cols[c]), "' (first at column ", d + 1, ")"));
    if (std::find(robot.channels.begin(), robot.channels.end(), cols[c]) == robot.channels.end())
      return Err(name, 1, static_cast<int>(c) + 1,
                 absl::StrCat("unknown channel '", Quote(cols[c]), "' for robot '", robot.name,
                              "' (known: ", absl::StrJoin(robot.channels, ", "), ")"));
    channels->emplace_back(cols[c]);
  }
  return absl::OkStatus();
}

// An occluded sample: an empty cell or NaN in any case (never in 't').
bool IsMissing(std::string_view cell) {
  return cell.empty() || (cell.size() == 3 && (cell[0] | 0x20) == 'n' && (cell[1] | 0x20) == 'a' &&
                          (cell[2] | 0x20) == 'n');
}

absl::Status ParseCsv(std::string_view csv, const std::string& name,
                      const internal::RobotInfo& robot, const RecordingLimits& limits,
                      Recording* rec) {
  csv = internal::StripBom(csv);
  Lines lines(csv);
  std::string_view line;
  if (!lines.Next(&line) || IsBlank(csv))
    return Err(name, 1, 0, "empty file; expected a header row starting with 't'");
  if (auto st = ParseHeader(line, name, robot, &rec->channels); !st.ok()) return st;

  const size_t ncols = rec->channels.size() + 1;
  const size_t expect_rows = std::min<size_t>(
      limits.max_rows, static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')));
  rec->t.reserve(expect_rows);
  rec->columns.assign(rec->channels.size(), {});
  for (auto& col : rec->columns) col.reserve(expect_rows);

  std::string_view prev_t_text;
  while (lines.Next(&line)) {
    const int ln = lines.number();
    if (IsBlank(line)) {
      if (IsBlank(lines.rest())) break;  // blank lines at the end are ignored
      return Err(name, ln, 0, "blank line between data rows");
    }
    if (rec->t.size() >= limits.max_rows)
      return Err(name, ln, 0,
                 absl::StrCat("more than ", limits.max_rows, " data rows (the limit)"));
    const size_t fields = static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (fields != ncols)
      return Err(name, ln, 0, absl::StrCat("row has ", fields, " fields, the header has ", ncols));
    const char* p = line.data();
    const char* const end = line.data() + line.size();
    for (size_t c = 0; c < ncols; ++c) {
      const char* comma =
          c + 1 == ncols ? end : static_cast<const char*>(std::memchr(p, ',', end - p));
      const std::string_view cell = Trim(std::string_view(p, comma - p));
      p = comma + 1;
      double v;
      if (c > 0 && IsMissing(cell)) {
        rec->columns[c - 1].push_back(NAN);
        continue;
      }
      if (!internal::ParseFiniteDouble(cell, &v)) {
        const std::string& col_name = c == 0 ? std::string("t") : rec->channels[c - 1];
        std::string got;
        if (cell.empty()) {
          got = "an empty cell";
        } else {
          double any;
          const char* cb = cell.data();
          auto r = std::from_chars(cb + (cell[0] == '+'), cb + cell.size(), any);
          const bool nonfinite = r.ptr == cb + cell.size() &&
                                 (r.ec == std::errc::result_out_of_range || !std::isfinite(any));
          got = absl::StrCat("'", Quote(cell), "'");
          if (nonfinite) {
            return Err(
                name, ln, static_cast<int>(c) + 1,
                absl::StrCat("column '", col_name, "': expected a finite number, got ", got));
          }
        }
        return Err(name, ln, static_cast<int>(c) + 1,
                   absl::StrCat("column '", col_name, "': expected a number, got ", got));
      }
      if (c == 0) {
        if (!rec->t.empty() && !(v > rec->t.back()))
          return Err(
              name, ln, 1,
              absl::StrCat("column 't': time must increase strictly, but ", Quote(cell),
                           " at line ", ln, " follows ", Quote(prev_t_text), " at line ", ln - 1));
        prev_t_text = cell;
        rec->t.push_back(v);
      } else {
        rec->columns[c - 1].push_back(v);
      }
    }
  }
  if (rec->t.size() < 2)
    return Err(name, 0, 0,
               absl::StrCat("need at least 2 data rows to know the sampling interval, got ",
                            rec->t.size()));
  return absl::OkStatus();
}

// Counts the missing cells and bridges them: linear in time between the channel's
// neighbouring values, the first or last value held at the ends. A channel without any value
// is an error (line 1, its column).
absl::Status BridgeMissing(const std::string& name, Recording* rec) {
  const size_t n = rec->t.size();
  rec->missing_per_channel.assign(rec->channels.size(), 0);
  for (size_t c = 0; c < rec->columns.size(); ++c) {
    std::vector<double>& x = rec->columns[c];
    std::vector<size_t> present;
    for (size_t i = 0; i < n; ++i)
      if (!std::isnan(x[i])) present.push_back(i);
    if (present.size() == n) continue;
    if (present.empty())
      return Err(name, 1, static_cast<int>(c) + 2,
                 absl::StrCat("channel '", rec->channels[c],
                              "' has no value: every cell is empty or NaN (leave the column out)"));
    if (rec->missing.empty()) rec->missing.assign(rec->columns.size(), {});
    rec->missing[c].assign(n, false);
    rec->missing_per_channel[c] = static_cast<int64_t>(n - present.size());
    rec->missing_cells += rec->missing_per_channel[c];
    size_t k = 0;  // present[k] is the first present row at or after i
    for (size_t i = 0; i < n; ++i) {
      while (k < present.size() && present[k] < i) ++k;
      if (k < present.size() && present[k] == i) continue;
      rec->missing[c][i] = true;
      if (k == 0) {
        x[i] = x[present.front()];
      } else if (k == present.size()) {
        x[i] = x[present.back()];
      } else {
        const size_t a = present[k - 1], b = present[k];
        const double w = (rec->t[i] - rec->t[a]) / (rec->t[b] - rec->t[a]);
        x[i] = x[a] + w * (x[b] - x[a]);
      }
    }
  }
  if (rec->missing.empty()) rec->missing_per_channel.clear();
  return absl::OkStatus();
}

// Nominal interval and dropped rows; data row r is on line r + 2 (no blank lines between).
absl::Status CheckSampling(const std::string& name, const RecordingLimits& limits, Recording* rec) {
  const size_t n = rec->t.size();
  std::vector<double> steps(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) steps[i] = rec->t[i + 1] - rec->t[i];
  std::vector<double> sorted = steps;
  // The lower median: with as many gaps as regular steps, the regular step wins.
  auto mid = sorted.begin() + (sorted.size() - 1) / 2;
  std::nth_element(sorted.begin(), mid, sorted.end());
  const double dt = *mid;
  rec->dt = dt;
  const double tol = limits.irregular_tolerance * dt;
  int64_t dropped = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    const double ratio = steps[i] / dt;
    const double k = std::round(ratio);
    const int line = static_cast<int>(i) + 3;
    if (k < 1 || std::fabs(steps[i] - k * dt) > tol * (1 + 1e-9)) {
      return Err(name, line, 1,
                 absl::StrCat("sampling is irregular at line ", line, ": step ", Num(steps[i]),
                              " s is not a multiple of ", Num(dt), " s within ",
                              Num(limits.irregular_tolerance * 100), "% (t = ", Num(rec->t[i + 1]),
                              " after ", Num(rec->t[i]), " at line ", line - 1, ")"));
    }
    if (k - 1 > static_cast<double>(limits.max_rows) ||
        dropped + static_cast<int64_t>(k) - 1 + static_cast<int64_t>(n) >
            static_cast<int64_t>(limits.max_rows))
      return Err(name, line, 1,
                 absl::StrCat("gap of ", Num(k), " intervals of ", Num(dt),
                              " s: with the rows missing the recording would exceed ",
                              limits.max_rows, " rows"));
    dropped += static_cast<int64_t>(k) - 1;
  }
  rec->dropped_rows = static_cast<int>(dropped);
  return absl::OkStatus();
}

}  // namespace

bool SameRate(double dt, double first) { return std::abs(dt - first) <= 0.01 * first; }

int Recording::ChannelIndex(std::string_view name) const {
  for (size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name) return static_cast<int>(i);
  return -1;
}

absl::StatusOr<std::string> SidecarRobot(std::string_view sidecar, const std::string& sidecar_name,
                                         const robots::RobotDescriptor* robot) {
  std::optional<internal::RobotInfo> given;
  if (robot) given = internal::InfoOf(*robot);
  auto side = internal::ParseSidecar(sidecar, sidecar_name, given ? &*given : nullptr);
  if (!side.ok()) return side.status();
  return side->meta.robot;
}

absl::StatusOr<Recording> ParseRecording(std::string_view csv, std::string_view sidecar,
                                         const std::string& csv_name,
                                         const std::string& sidecar_name,
                                         const RecordingLimits& limits,
                                         const robots::RobotDescriptor* robot) {
  const size_t total = csv.size() + sidecar.size();
  if (total > limits.max_bytes)
    return Err(csv_name, 0, 0,
               absl::StrCat("recording is ", total, " bytes (CSV ", csv.size(), " + sidecar ",
                            sidecar.size(), "), over the limit of ", limits.max_bytes, " bytes"));
  std::optional<internal::RobotInfo> given;
  if (robot) given = internal::InfoOf(*robot);
  auto side = internal::ParseSidecar(sidecar, sidecar_name, given ? &*given : nullptr);
  if (!side.ok()) return side.status();

  Recording rec;
  rec.meta = std::move(side->meta);
  if (auto st = ParseCsv(csv, csv_name, *side->robot, limits, &rec); !st.ok()) return st;
  for (const auto& [ch, mark] : side->channel_marks)
    if (rec.ChannelIndex(ch) < 0)
      return Err(sidecar_name, mark.first, mark.second,
                 absl::StrCat("key 'channels.", ch, "': channel '", ch, "' is not a column of ",
                              csv_name));
  if (rec.meta.command_kind == "playback")
    for (const std::string& input : side->robot->inputs)
      if (rec.ChannelIndex(input) < 0)
        return Err(sidecar_name, side->command_mark.first, side->command_mark.second,
                   absl::StrCat("key 'command.kind': a playback drives every actuator from its "
                                "column, and ", csv_name, " has no column '", input,
                                "' (needed: ", absl::StrJoin(side->robot->inputs, ", "), ")"));
  if (auto st = CheckSampling(csv_name, limits, &rec); !st.ok()) return st;
  if (auto st = BridgeMissing(csv_name, &rec); !st.ok()) return st;
  if (auto st = internal::CheckMarkerFrame(csv_name, *side->robot, rec); !st.ok()) return st;
  return rec;
}

std::string ContentHash(std::string_view csv, std::string_view sidecar) {
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  const char zero = 0;
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1 ||
      EVP_DigestUpdate(ctx.get(), csv.data(), csv.size()) != 1 ||
      EVP_DigestUpdate(ctx.get(), &zero, 1) != 1 ||
      EVP_DigestUpdate(ctx.get(), sidecar.data(), sidecar.size()) != 1 ||
      EVP_DigestFinal_ex(ctx.get(), digest, &len) != 1)
    std::abort();  // only on allocation failure inside OpenSSL
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out(2 * len, '0');
  for (unsigned int i = 0; i < len; ++i) {
    out[2 * i] = kHex[digest[i] >> 4];
    out[2 * i + 1] = kHex[digest[i] & 15];
  }
  return out;
}

std::vector<std::string> KnownChannels(const std::string& robot) {
  const internal::RobotInfo* r = internal::FindRobot(robot);
  if (!r) return {};
  return {r->channels.begin(), r->channels.end() - static_cast<std::ptrdiff_t>(r->inputs.size())};
}

}  // namespace gaitforge::recording
