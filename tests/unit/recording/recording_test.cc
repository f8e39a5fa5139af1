// The recording parser (services/recording, docs/recording-format.md): round trips, the
// writer's format, line endings, dropped rows, every error with its FILE:LINE:COLUMN, the
// content hash, and parse speed.
#include "services/recording/recording.h"

#include <gtest/gtest.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
#include "absl/strings/str_join.h"
#include "robots/registry.h"

namespace gaitforge::recording {
namespace {

// 13 caterpillar genes.
constexpr char kGenes[] = "[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85, 0.8]";

std::string MinimalSidecar() {
  return std::string(
             "{\n  \"robot\": \"caterpillar\",\n  \"command\": {\"kind\": \"gait\", "
             "\"genes\": ") +
         kGenes + "}\n}\n";
}

std::string Fmt(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = 0; (p = s.find(from, p)) != std::string::npos; p += to.size())
    s.replace(p, from.size(), to);
  return s;
}

// The message of a failed parse, or "OK".
std::string ErrorOf(const std::string& csv, const std::string& sidecar,
                    const RecordingLimits& limits = {}) {
  auto r = ParseRecording(csv, sidecar, "rec.csv", "rec.csv.json", limits);
  if (r.ok()) return "OK";
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  return std::string(r.status().message());
}

// What workers/tools/sim_tool.cc WriteRecording writes, built the same way.
std::string JsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
      continue;
    }
    out += c;
  }
  return out;
}

struct SimText {
  std::string csv, sidecar;
};

SimText SimToolRecording(int rows, double t0, double rate, const std::string& params_path,
                         const std::vector<double>& genes, const std::string& note) {
  SimText out;
  out.csv = "t";
  for (int i = 1; i <= 6; ++i)
    out.csv +=
        ",m" + std::to_string(i) + ".x,m" + std::to_string(i) + ".y,m" + std::to_string(i) + ".z";
  out.csv += "\n";
  for (int k = 0; k < rows; ++k) {
    const double t = t0 + k / rate;
    out.csv += Fmt("%.6f", t);
    for (int i = 0; i < 6; ++i) {
      out.csv += Fmt(",%.9g", 0.0095 + 0.053 * i + 0.004 * std::sin(7 * t + i));
      out.csv += Fmt(",%.9g", 1e-7 * std::cos(3 * t + i));
      out.csv += Fmt(",%.9g", 0.0125 + 0.003 * std::sin(5 * t - i));
    }
    out.csv += "\n";
  }
  out.sidecar = "{\n  \"robot\": \"caterpillar\",\n  \"parameters\": \"" + JsonEscape(params_path) +
                "\",\n  \"command\": {\"kind\": \"gait\", \"genes\": [";
  for (size_t i = 0; i < genes.size(); ++i) out.sidecar += (i ? ", " : "") + Fmt("%.17g", genes[i]);
  out.sidecar +=
      "]},\n  \"source\": \"simulation\",\n  \"note\": \"" + JsonEscape(note) + "\"\n}\n";
  return out;
}

TEST(RecordingTest, GoodFileRoundTripsExactly) {
  std::vector<std::string> texts[4];  // t, m1.x, m2.y, m6.z as printed
  std::string csv = "t,m1.x,m2.y,m6.z\n";
  for (int k = 0; k < 50; ++k) {
    texts[0].push_back(Fmt("%.6f", 0.5 + k * 0.01));
    texts[1].push_back(Fmt("%.9g", 0.0123456789 * k - 0.1));
    texts[2].push_back(Fmt("%.9g", -3.3e-6 * k));
    texts[3].push_back(Fmt("%.9g", 1e-12 + 0.0125 * std::sin(k)));
    csv += texts[0].back() + "," + texts[1].back() + "," + texts[2].back() + "," + texts[3].back() +
           "\n";
  }
  const std::string sidecar = std::string(R"({
  "robot": "caterpillar",
  "parameters": "robots/caterpillar/robot.yaml",
  "overrides": {"lump_mass": 0.031, "friction": 1e3},
  "command": {"kind": "gait", "genes": )") +
                              kGenes + R"(},
  "source": "hardware",
  "note": "take 3 \"fast\"\nsecond line \u00e9 \\ end",
  "channels": {"m1.x": {"unit": "m"}, "m6.z": {"unit": "m"}}
}
)";
  auto r = ParseRecording(csv, sidecar, "rec.csv", "rec.csv.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->channels, (std::vector<std::string>{"m1.x", "m2.y", "m6.z"}));
  ASSERT_EQ(r->t.size(), 50u);
  ASSERT_EQ(r->columns.size(), 3u);
  for (int k = 0; k < 50; ++k) {
    EXPECT_EQ(r->t[k], std::strtod(texts[0][k].c_str(), nullptr)) << k;
    EXPECT_EQ(Fmt("%.6f", r->t[k]), texts[0][k]);
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(r->columns[c].size(), 50u);
      EXPECT_EQ(r->columns[c][k], std::strtod(texts[c + 1][k].c_str(), nullptr)) << c << "," << k;
      EXPECT_EQ(Fmt("%.9g", r->columns[c][k]), texts[c + 1][k]);
    }
  }
  EXPECT_NEAR(r->dt, 0.01, 1e-9);
  EXPECT_EQ(r->dropped_rows, 0);
  EXPECT_EQ(r->ChannelIndex("m2.y"), 1);
  EXPECT_EQ(r->ChannelIndex("m3.x"), -1);
  EXPECT_EQ(r->ChannelIndex("t"), -1);
  const RecordingMeta& m = r->meta;
  EXPECT_EQ(m.robot, "caterpillar");
  EXPECT_EQ(m.parameters, "robots/caterpillar/robot.yaml");
  EXPECT_EQ(m.overrides, (std::map<std::string, double>{{"friction", 1000}, {"lump_mass", 0.031}}));
  EXPECT_EQ(m.command_kind, "gait");
  EXPECT_EQ(m.genes, (std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.35, 0.45, 0.55, 0.65,
                                          0.75, 0.85, 0.8}));
  EXPECT_EQ(m.source, "hardware");
  EXPECT_EQ(m.note, "take 3 \"fast\"\nsecond line \xC3\xA9 \\ end");
  EXPECT_EQ(m.channel_units, (std::map<std::string, std::string>{{"m1.x", "m"}, {"m6.z", "m"}}));
}

TEST(RecordingTest, SimToolWriterOutputParses) {
  const std::vector<double> genes = {
      0.1, 0.25, 0.4, 0.55, 0.7, 0.85, 0.3, 0.45, 0.6, 0.75, 0.9, 0.05, 0.8000000000000000444};
  // 2 settling cycles of 0.8 s, then 3 cycles at 100 Hz, as `trajectory` samples them.
  const SimText s = SimToolRecording(241, 1.6, 100, "C:\\params\\cat \"v2\".yaml", genes,
                                     "rank 0\tgeneration 12\nseed 7");
  auto r = ParseRecording(s.csv, s.sidecar, "sim.csv", "sim.csv.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->channels, KnownChannels("caterpillar"));
  EXPECT_EQ(r->t.size(), 241u);
  EXPECT_NEAR(r->dt, 0.01, 1e-6);
  EXPECT_EQ(r->dropped_rows, 0);
  EXPECT_EQ(r->meta.genes, genes);  // %.17g round-trips exactly
  EXPECT_EQ(r->meta.parameters, "C:\\params\\cat \"v2\".yaml");
  EXPECT_EQ(r->meta.note, "rank 0\tgeneration 12\nseed 7");
  EXPECT_EQ(r->meta.source, "simulation");
  EXPECT_EQ(r->meta.command_kind, "gait");

  // Times k / 240 printed with %.6f: the steps differ by 1 us, well within the tolerance.
  const SimText fast = SimToolRecording(100, 2.422, 240, "p.yaml", genes, "");
  auto f = ParseRecording(fast.csv, fast.sidecar, "fast.csv", "fast.csv.json");
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->dt, 1.0 / 240, 2e-6);
  EXPECT_EQ(f->dropped_rows, 0);
}

TEST(RecordingTest, CrlfBomAndTrailingNewlinesAccepted) {
  const std::string csv = "t,m1.x,m1.z\n0,0.01,0.025\n0.01,0.02,0.026\n0.02,0.03,0.027\n";
  auto lf = ParseRecording(csv, MinimalSidecar(), "a.csv", "a.csv.json");
  ASSERT_TRUE(lf.ok()) << lf.status();

  const std::string bom = "\xEF\xBB\xBF";
  auto crlf = ParseRecording(bom + Replace(csv, "\n", "\r\n"),
                             bom + Replace(MinimalSidecar(), "\n", "\r\n"), "b.csv", "b.csv.json");
  ASSERT_TRUE(crlf.ok()) << crlf.status();
  EXPECT_EQ(crlf->channels, lf->channels);
  EXPECT_EQ(crlf->t, lf->t);
  EXPECT_EQ(crlf->columns, lf->columns);

  // No final newline; blank lines at the end; spaces around cells.
  auto no_nl = ParseRecording(csv.substr(0, csv.size() - 1), MinimalSidecar(), "c.csv", "c.json");
  ASSERT_TRUE(no_nl.ok()) << no_nl.status();
  EXPECT_EQ(no_nl->columns, lf->columns);
  auto trailing = ParseRecording(csv + "\n\r\n", MinimalSidecar(), "d.csv", "d.json");
  ASSERT_TRUE(trailing.ok()) << trailing.status();
  EXPECT_EQ(trailing->t.size(), 3u);
  auto spaced = ParseRecording("t, m1.x ,m1.z\n0, 0.01,0.025\n0.01,0.02 ,0.026\n0.02,0.03,0.027\n",
                               MinimalSidecar(), "e.csv", "e.json");
  ASSERT_TRUE(spaced.ok()) << spaced.status();
  EXPECT_EQ(spaced->columns, lf->columns);

  // Line numbers stay those of the file with CRLF and a BOM.
  EXPECT_EQ(ErrorOf(bom + "t,m1.x\r\n0,1\r\n0.01,x\r\n", MinimalSidecar()),
            "rec.csv:3:2: column 'm1.x': expected a number, got 'x'");
  EXPECT_EQ(ErrorOf(csv, Replace(MinimalSidecar(), "\n}", ",\r\n  \"colour\": 1\r\n}")),
            "rec.csv.json:4:3: unknown key 'colour' (known: robot, parameters, overrides, "
            "command, source, note, channels)");
}

// The robot a sidecar names, checked as the parser checks it (a diagnosis spec that names
// no robot takes it from here).
TEST(RecordingTest, SidecarRobotIsTheRobotItNamesOrAnErrorWithItsPlace) {
  auto robot = SidecarRobot(MinimalSidecar(), "a.csv.json");
  ASSERT_TRUE(robot.ok()) << robot.status();
  EXPECT_EQ(*robot, "caterpillar");
  auto blimp = SidecarRobot(Replace(MinimalSidecar(), "caterpillar", "blimp"), "b.csv.json");
  ASSERT_FALSE(blimp.ok());
  EXPECT_NE(blimp.status().message().find("b.csv.json:2:"), std::string::npos) << blimp.status();
  EXPECT_NE(blimp.status().message().find("blimp"), std::string::npos) << blimp.status();
}

TEST(RecordingTest, NumberForms) {
  auto r = ParseRecording("t,m1.x\n0,1e-3\n1e-2,+2.5E+1\n.02,-.5\n0.03,5.\n0.04,-0\n0.05,1e-400\n",
                          MinimalSidecar(), "n.csv", "n.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->columns[0], (std::vector<double>{1e-3, 25, -0.5, 5, -0.0, 0}));
  EXPECT_EQ(r->t[1], 0.01);
}

TEST(RecordingTest, DroppedRowsAreCounted) {
  // Rows at 0.03 and 0.04 missing; small jitter elsewhere.
  auto r = ParseRecording("t,m3.z\n0,1\n0.0101,1\n0.02,1\n0.0499,1\n0.06,1\n0.0702,1\n",
                          MinimalSidecar(), "g.csv", "g.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_NEAR(r->dt, 0.01, 2e-4);
  EXPECT_EQ(r->dropped_rows, 2);

  // Two gaps of 3 and 4 intervals: 2 + 3 dropped.
  auto g = ParseRecording("t,m3.z\n0,1\n0.1,1\n0.4,1\n0.5,1\n0.9,1\n1.0,1\n", MinimalSidecar(),
                          "h.csv", "h.json");
  ASSERT_TRUE(g.ok()) << g.status();
  EXPECT_NEAR(g->dt, 0.1, 1e-12);
  EXPECT_EQ(g->dropped_rows, 5);

  // Two rows one gap apart: the lower median is the gap itself, nothing dropped.
  auto two = ParseRecording("t,m3.z\n0,1\n0.5,1\n", MinimalSidecar(), "i.csv", "i.json");
  ASSERT_TRUE(two.ok()) << two.status();
  EXPECT_EQ(two->dt, 0.5);
  EXPECT_EQ(two->dropped_rows, 0);
}

const std::string kFullCsv = "t,m1.x,m1.z\n0,1,2\n0.01,1,2\n0.02,1,2\n";

TEST(RecordingTest, EmptyAndNaNCellsAreMissingSamplesBridgedInTime) {
  // m1.x occluded at 0.01 (empty) and 0.02..0.03 (NaN, nan); m1.z at the start and the end.
  auto r = ParseRecording(
      "t,m1.x,m1.z\n0,1,\n0.01,,NAN\n0.02,NaN,2\n0.03,nan,3\n0.04,5,4\n0.05,6,\n",
      MinimalSidecar(), "occ.csv", "occ.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->t.size(), 6u);
  EXPECT_EQ(r->dropped_rows, 0);
  EXPECT_EQ(r->missing_cells, 6);
  EXPECT_EQ(r->missing_per_channel, (std::vector<int64_t>{3, 3}));
  // Linear in time between 1 at 0 and 5 at 0.04; the ends hold the nearest value.
  ASSERT_EQ(r->columns[0].size(), 6u);
  EXPECT_DOUBLE_EQ(r->columns[0][1], 2);
  EXPECT_DOUBLE_EQ(r->columns[0][2], 3);
  EXPECT_DOUBLE_EQ(r->columns[0][3], 4);
  EXPECT_EQ(r->columns[0][4], 5);
  EXPECT_EQ(r->columns[1], (std::vector<double>{2, 2, 2, 3, 4, 4}));
  EXPECT_EQ(r->missing[0], (std::vector<bool>{false, true, true, true, false, false}));
  EXPECT_EQ(r->missing[1], (std::vector<bool>{true, true, false, false, false, true}));

  // Bridging works across dropped rows too: time, not row count, sets the weights.
  auto g = ParseRecording("t,m1.x\n0,0\n0.01,\n0.04,4\n0.05,5\n", MinimalSidecar(), "g.csv",
                          "g.json");
  ASSERT_TRUE(g.ok()) << g.status();
  EXPECT_EQ(g->dropped_rows, 2);
  EXPECT_DOUBLE_EQ(g->columns[0][1], 1);

  // Nothing missing: no mask, nothing counted.
  auto full = ParseRecording(kFullCsv, MinimalSidecar(), "f.csv", "f.json");
  ASSERT_TRUE(full.ok()) << full.status();
  EXPECT_EQ(full->missing_cells, 0);
  EXPECT_TRUE(full->missing.empty());
  EXPECT_TRUE(full->missing_per_channel.empty());
}

struct ErrorCase {
  const char* name;
  std::string csv;
  std::string sidecar;
  std::string expected;  // the whole message when `exact`, else a fragment
  bool exact = true;
};

void PrintTo(const ErrorCase& c, std::ostream* os) { *os << c.name; }

class RecordingErrorTest : public testing::TestWithParam<ErrorCase> {};

TEST_P(RecordingErrorTest, ReportsWhereAndWhat) {
  const ErrorCase& c = GetParam();
  const std::string msg = ErrorOf(c.csv, c.sidecar.empty() ? MinimalSidecar() : c.sidecar);
  if (c.exact) {
    EXPECT_EQ(msg, c.expected);
  } else {
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
  }
}

const std::string kCsv = "t,m1.x,m1.z\n0,1,2\n0.01,1,2\n0.02,1,2\n";

std::string Side(const std::string& body) { return "{\n" + body + "\n}\n"; }
const std::string kRobot = "  \"robot\": \"caterpillar\",\n";
const std::string kCommand =
    std::string("  \"command\": {\"kind\": \"gait\", \"genes\": ") + kGenes + "}";

INSTANTIATE_TEST_SUITE_P(
    Csv, RecordingErrorTest,
    testing::Values(
        ErrorCase{"NonNumeric", "t,m1.x,m3.z\n0,1,2\n0.01,1,abc\n", "",
                  "rec.csv:3:3: column 'm3.z': expected a number, got 'abc'"},
        ErrorCase{"EmptyTime", "t,m1.x,m1.z\n0,1,2\n,1,2\n", "",
                  "rec.csv:3:1: column 't': expected a number, got an empty cell"},
        ErrorCase{"NaNTime", "t,m1.x,m1.z\n0,1,2\nnan,1,2\n", "",
                  "rec.csv:3:1: column 't': expected a finite number, got 'nan'"},
        ErrorCase{"ChannelWithoutValue", "t,m1.x,m1.z\n0,1,\n0.01,1,NaN\n", "",
                  "rec.csv:1:3: channel 'm1.z' has no value: every cell is empty or NaN (leave "
                  "the column out)"},
        ErrorCase{"NaNWord", "t,m1.x,m1.z\n0,1,2\n0.01,NaNa,2\n", "",
                  "rec.csv:3:2: column 'm1.x': expected a number, got 'NaNa'"},
        ErrorCase{"Inf", "t,m1.x,m1.z\n0,1,2\n0.01,1,2\n0.02,1,-inf\n", "",
                  "rec.csv:4:3: column 'm1.z': expected a finite number, got '-inf'"},
        ErrorCase{"Overflow", "t,m1.x,m1.z\n0,1e999,2\n", "",
                  "rec.csv:2:2: column 'm1.x': expected a finite number, got '1e999'"},
        ErrorCase{"InvalidUtf8", "t,m1.x\n0,1\xff\n", "",
                  "rec.csv:2:2: column 'm1.x': expected a number, got '1\\xff'"},
        ErrorCase{
            "LongCellShortened", "t,m1.x\n0," + std::string(50, '7') + "x\n", "",
            "rec.csv:2:2: column 'm1.x': expected a number, got '" + std::string(40, '7') + "...'"},
        ErrorCase{"Hex", "t,m1.x,m1.z\n0,0x10,2\n", "",
                  "rec.csv:2:2: column 'm1.x': expected a number, got '0x10'"},
        ErrorCase{"DecimalComma", "t,m1.x\n0,1\n0.01,\"1,5\"\n", "",
                  "rec.csv:3: row has 3 fields, the header has 2"},
        ErrorCase{"BadTime", "t,m1.x\n0,1\n0.01s,1\n", "",
                  "rec.csv:3:1: column 't': expected a number, got '0.01s'"},
        ErrorCase{"MissingT", "time,m1.x\n0,1\n0.01,1\n", "",
                  "rec.csv:1:1: the first column must be 't' (time in s), got 'time'; there "
                  "is no 't' column"},
        ErrorCase{"TNotFirst", "m1.x,t\n1,0\n1,0.01\n", "",
                  "rec.csv:1:1: the first column must be 't' (time in s), got 'm1.x'; 't' is "
                  "column 2"},
        ErrorCase{"Semicolons", "t;m1.x\n0;1\n", "",
                  "rec.csv:1:1: the first column must be 't' (time in s), got 't;m1.x'; there "
                  "is no 't' column (columns are separated by ',')"},
        ErrorCase{"Duplicate", "t,m1.x,m1.z,m1.x\n0,1,2,3\n", "",
                  "rec.csv:1:4: duplicate column 'm1.x' (first at column 2)"},
        ErrorCase{"DuplicateT", "t,m1.x,t\n0,1,2\n", "",
                  "rec.csv:1:3: duplicate column 't' (first at column 1)"},
        ErrorCase{"UnknownChannel", "t,m1.x,m7.x\n0,1,2\n", "",
                  "rec.csv:1:3: unknown channel 'm7.x' for robot 'caterpillar' (known: m1.x, "
                  "m1.y, m1.z, m2.x",
                  false},
        ErrorCase{"JointChannelOnCaterpillar", "t,T1.angle\n0,1\n", "",
                  "rec.csv:1:2: unknown channel 'T1.angle' for robot 'caterpillar'", false},
        ErrorCase{"EmptyColumnName", "t,m1.x,,m1.z\n", "", "rec.csv:1:3: empty column name"},
        ErrorCase{"NoChannels", "t\n0\n0.01\n", "", "rec.csv:1: no channel columns after 't'"},
        ErrorCase{"EmptyFile", "", "",
                  "rec.csv:1: empty file; expected a header row starting with 't'"},
        ErrorCase{"TooFewFields", "t,m1.x,m1.z\n0,1,2\n0.01,1\n", "",
                  "rec.csv:3: row has 2 fields, the header has 3"},
        ErrorCase{"TooManyFields", "t,m1.x,m1.z\n0,1,2\n0.01,1,2\n0.02,1,2,3\n", "",
                  "rec.csv:4: row has 4 fields, the header has 3"},
        ErrorCase{"TimeDecreases", "t,m1.x\n0,1\n0.02,1\n0.01,1\n", "",
                  "rec.csv:4:1: column 't': time must increase strictly, but 0.01 at line 4 "
                  "follows 0.02 at line 3"},
        ErrorCase{"TimeRepeats", "t,m1.x\n0,1\n0.010,1\n0.01,1\n", "",
                  "rec.csv:4:1: column 't': time must increase strictly, but 0.01 at line 4 "
                  "follows 0.010 at line 3"},
        ErrorCase{"Irregular", "t,m1.x\n0,1\n0.01,1\n0.02,1\n0.03,1\n0.0473,1\n0.0573,1\n", "",
                  "rec.csv:6:1: sampling is irregular at line 6: step 0.0173 s is not a "
                  "multiple of 0.01 s within 5% (t = 0.0473 after 0.03 at line 5)"},
        ErrorCase{"StepTooShort", "t,m1.x\n0,1\n0.01,1\n0.02,1\n0.025,1\n0.035,1\n", "",
                  "rec.csv:5:1: sampling is irregular at line 5: step 0.005 s is not a "
                  "multiple of 0.01 s within 5%",
                  false},
        ErrorCase{"OneRow", "t,m1.x\n0,1\n", "",
                  "rec.csv: need at least 2 data rows to know the sampling interval, got 1"},
        ErrorCase{"HeaderOnly", "t,m1.x\n", "",
                  "rec.csv: need at least 2 data rows to know the sampling interval, got 0"},
        ErrorCase{"BlankLineInside", "t,m1.x\n0,1\n\n0.01,1\n", "",
                  "rec.csv:3: blank line between data rows"}),
    [](const testing::TestParamInfo<ErrorCase>& i) { return std::string(i.param.name); });

INSTANTIATE_TEST_SUITE_P(
    Sidecar, RecordingErrorTest,
    testing::Values(
        ErrorCase{"UnknownRobot", kCsv, Side("  \"robot\": \"centipede\",\n" + kCommand),
                  "rec.csv.json:2:12: unknown robot 'centipede' (built in: " +
                      absl::StrJoin(robots::RobotNames(), ", ") +
                      "; another robot's recording needs its descriptor)"},
        ErrorCase{"RobotNotString", kCsv, Side("  \"robot\": 5,\n" + kCommand),
                  "rec.csv.json:2:12: key 'robot': expected a string, got the number 5"},
        ErrorCase{"MissingRobot", kCsv, Side(kCommand),
                  "rec.csv.json:1:1: missing required key 'robot'"},
        ErrorCase{"MissingCommand", kCsv, Side("  \"robot\": \"caterpillar\""),
                  "rec.csv.json:1:1: missing required key 'command'"},
        ErrorCase{"MissingGenes", kCsv, Side(kRobot + "  \"command\": {\"kind\": \"gait\"}"),
                  "rec.csv.json:3:14: missing required key 'command.genes'"},
        ErrorCase{"MissingKind", kCsv, Side(kRobot + "  \"command\": {\"genes\": []}"),
                  "rec.csv.json:3:14: missing required key 'command.kind'"},
        ErrorCase{"UnknownKind", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"walk\", \"genes\": []}"),
                  "rec.csv.json:3:23: key 'command.kind': unknown command kind 'walk' "
                  "(known: gait, playback, path)"},
        ErrorCase{"WrongGeneCount", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"gait\", \"genes\": [1, 2]}"),
                  "rec.csv.json:3:40: key 'command.genes': the caterpillar takes 13 genes "
                  "(a_T1 a_T2 a_T3 a_B1 a_B2 a_B3 d_T1 d_T2 d_T3 d_B1 d_B2 d_B3 T), got 2"},
        ErrorCase{"GeneNotNumber", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"gait\", \"genes\": [1, \"x\"]}"),
                  "rec.csv.json:3:44: key 'command.genes[1]': expected a number, got the "
                  "string \"x\""},
        ErrorCase{"GenesNotArray", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"gait\", \"genes\": {}}"),
                  "rec.csv.json:3:40: key 'command.genes': expected an array of numbers, got "
                  "an object"},
        ErrorCase{"GeneOverflow", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"gait\", \"genes\": [1e999]}"),
                  "rec.csv.json:3:41: key 'command.genes[0]': expected a finite number, got "
                  "1e999"},
        ErrorCase{"UnknownKey", kCsv, Side(kRobot + "  \"colour\": \"green\",\n" + kCommand),
                  "rec.csv.json:3:3: unknown key 'colour' (known: robot, parameters, "
                  "overrides, command, source, note, channels)"},
        ErrorCase{"UnknownCommandKey", kCsv,
                  Side(kRobot + "  \"command\": {\"kind\": \"gait\", \"speed\": 1}"),
                  "rec.csv.json:3:31: unknown key 'command.speed' (known in command: kind, "
                  "genes)"},
        ErrorCase{"DuplicateKey", kCsv, Side(kRobot + kCommand + ",\n  \"robot\": \"caterpillar\""),
                  "rec.csv.json:4:3: duplicate key 'robot' (first at line 2)"},
        ErrorCase{"OverrideNotNumber", kCsv,
                  Side(kRobot + "  \"overrides\": {\"mass\": \"heavy\"},\n" + kCommand),
                  "rec.csv.json:3:25: key 'overrides.mass': expected a number, got the string "
                  "\"heavy\""},
        ErrorCase{"OverridesNotObject", kCsv, Side(kRobot + "  \"overrides\": [1],\n" + kCommand),
                  "rec.csv.json:3:16: key 'overrides': expected an object, got an array"},
        ErrorCase{"NoteNotString", kCsv, Side(kRobot + kCommand + ",\n  \"note\": true"),
                  "rec.csv.json:4:11: key 'note': expected a string, got true"},
        ErrorCase{"ChannelUnit", kCsv,
                  Side(kRobot + "  \"channels\": {\"m1.x\": {\"unit\": \"mm\"}},\n" + kCommand),
                  "rec.csv.json:3:33: key 'channels.m1.x.unit': channel 'm1.x' is in m, not "
                  "'mm'"},
        ErrorCase{"ChannelNotInCsv", kCsv,
                  Side(kRobot + "  \"channels\": {\"m2.x\": {\"unit\": \"m\"}},\n" + kCommand),
                  "rec.csv.json:3:16: key 'channels.m2.x': channel 'm2.x' is not a column of "
                  "rec.csv"},
        ErrorCase{"ChannelUnknown", kCsv,
                  Side(kRobot + "  \"channels\": {\"m9.q\": {\"unit\": \"m\"}},\n" + kCommand),
                  "rec.csv.json:3:16: key 'channels.m9.q': unknown channel 'm9.q' for robot "
                  "'caterpillar'"},
        ErrorCase{"ChannelExtraKey", kCsv,
                  Side(kRobot + "  \"channels\": {\"m1.x\": {\"unit\": \"m\", \"gain\": 2}},\n" +
                       kCommand),
                  "rec.csv.json:3:38: unknown key 'channels.m1.x.gain' (known in "
                  "channels.m1.x: unit)"},
        ErrorCase{"TrailingComma", kCsv, Side(kRobot + kCommand + ","),
                  "rec.csv.json:4:1: not valid JSON: expected a member name in double quotes, "
                  "got '}'"},
        ErrorCase{"SingleQuotes", kCsv, Side("  'robot': 'caterpillar'"),
                  "rec.csv.json:2:3: not valid JSON: expected a member name in double quotes, "
                  "got '''"},
        ErrorCase{"YamlNotJson", kCsv, "robot: caterpillar\n",
                  "rec.csv.json:1:1: not valid JSON: expected a JSON object ('{'), got 'r'"},
        ErrorCase{"TextAfterObject", kCsv, MinimalSidecar() + "{}\n",
                  "rec.csv.json:5:1: not valid JSON: unexpected '{' after the JSON object"},
        ErrorCase{"EmptySidecar", kCsv, " \n",
                  "rec.csv.json:2:1: not valid JSON: expected a JSON object ('{'), got an "
                  "empty file"},
        ErrorCase{"Unterminated", kCsv, "{\"robot\": \"caterp",
                  "rec.csv.json:1:18: not valid JSON: unterminated string"},
        ErrorCase{"RawNewlineInString", kCsv, "{\"note\": \"a\nb\"}",
                  "rec.csv.json:1:12: not valid JSON: control character in a string (write it "
                  "as an escape)"},
        ErrorCase{"BadNumber", kCsv, "{\"x\": 01}",
                  "rec.csv.json:1:8: not valid JSON: unexpected '1' in a number"},
        ErrorCase{"NonAscii", kCsv, "{\"robot\": \xC3\xA9}",
                  "rec.csv.json:1:11: not valid JSON: expected a value, got the byte 0xc3"},
        ErrorCase{"NaNLiteral", kCsv, "{\"x\": NaN}",
                  "rec.csv.json:1:7: not valid JSON: expected a value, got 'N'"}),
    [](const testing::TestParamInfo<ErrorCase>& i) { return std::string(i.param.name); });

TEST(RecordingTest, SizeAndRowLimits) {
  RecordingLimits small;
  small.max_bytes = 50;
  const std::string side = MinimalSidecar();
  EXPECT_EQ(ErrorOf(kCsv, side, small),
            "rec.csv: recording is " + std::to_string(kCsv.size() + side.size()) + " bytes (CSV " +
                std::to_string(kCsv.size()) + " + sidecar " + std::to_string(side.size()) +
                "), over the limit of 50 bytes");
  small.max_bytes = kCsv.size() + side.size();
  EXPECT_EQ(ErrorOf(kCsv, side, small), "OK");

  RecordingLimits rows;
  rows.max_rows = 2;
  EXPECT_EQ(ErrorOf(kCsv, side, rows), "rec.csv:4: more than 2 data rows (the limit)");
  rows.max_rows = 3;
  EXPECT_EQ(ErrorOf(kCsv, side, rows), "OK");
  // A gap that would need more rows than the limit.
  EXPECT_EQ(ErrorOf("t,m1.x\n0,1\n0.01,1\n0.02,1\n100,1\n", side),
            "OK");  // 9997 dropped, within 2e6
  rows.max_rows = 1000;
  EXPECT_EQ(ErrorOf("t,m1.x\n0,1\n0.01,1\n0.02,1\n100,1\n", side, rows),
            "rec.csv:5:1: gap of 9998 intervals of 0.01 s: with the rows missing the recording "
            "would exceed 1000 rows");

  RecordingLimits tight;
  tight.irregular_tolerance = 0.01;
  EXPECT_EQ(ErrorOf("t,m1.x\n0,1\n0.01,1\n0.02,1\n0.0303,1\n", side, tight),
            "rec.csv:5:1: sampling is irregular at line 5: step 0.0103 s is not a multiple of "
            "0.01 s within 1% (t = 0.0303 after 0.02 at line 4)");
  EXPECT_EQ(ErrorOf("t,m1.x\n0,1\n0.01,1\n0.02,1\n0.0303,1\n", side), "OK");
}

TEST(RecordingTest, ContentHash) {
  // sha256 of "abc\0def" and of "\0" (printf 'abc\0def' | sha256sum).
  EXPECT_EQ(ContentHash("abc", "def"),
            "516a5e926ce20c5f4d80f00e1a01abdf14986def6588d6abeed9fce090bc660c");
  EXPECT_EQ(ContentHash("", ""),
            "6e340b9cffb37a989ca544e6bb780a2c78901d3fb33738768511a30617afa01d");

  const std::string side = MinimalSidecar();
  const std::string h = ContentHash(kCsv, side);
  EXPECT_EQ(h.size(), 64u);
  EXPECT_EQ(h.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ(ContentHash(kCsv, side), h);
  std::string csv2 = kCsv;
  csv2[csv2.size() - 2] = '3';
  EXPECT_NE(ContentHash(csv2, side), h);
  std::string side2 = side;
  side2[side2.find("0.85")] = '1';
  EXPECT_NE(ContentHash(kCsv, side2), h);
  // The zero byte separates the two: moving bytes across the boundary changes the hash.
  EXPECT_NE(ContentHash("ab", "c"), ContentHash("a", "bc"));
  EXPECT_NE(ContentHash(kCsv + side, ""), ContentHash(kCsv, side));
}

TEST(RecordingTest, KnownChannels) {
  const auto ch = KnownChannels("caterpillar");
  ASSERT_EQ(ch.size(), 18u);
  EXPECT_EQ(ch.front(), "m1.x");
  EXPECT_EQ(ch[4], "m2.y");
  EXPECT_EQ(ch.back(), "m6.z");
  EXPECT_TRUE(KnownChannels("centipede").empty());
}

// 1e5 rows of t and 18 markers: well under a second (ctest runs this build at -O2).
TEST(RecordingTest, ParsesAHundredThousandRows) {
  const int rows = 100000;
  std::string csv = "t";
  for (const auto& c : KnownChannels("caterpillar")) csv += "," + c;
  csv += "\n";
  csv.reserve(rows * 19 * 13);
  char buf[32];
  for (int k = 0; k < rows; ++k) {
    auto put = [&](double v) {
      auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 9);
      csv.append(buf, p);
    };
    put(k * 0.01);
    for (int c = 0; c < 18; ++c) {  // m1.x, m1.y, m1.z, m2.x, ...: x 0.032 m apart
      csv += ',';
      put(c % 3 == 0 ? 0.032 * (c / 3) + 1e-7 * k : c % 3 == 1 ? 0.0 : 0.0125 + 1e-4 * c + 1e-7 * k);
    }
    csv += '\n';
  }
  const auto start = std::chrono::steady_clock::now();
  auto r = ParseRecording(csv, MinimalSidecar(), "big.csv", "big.csv.json");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->t.size(), static_cast<size_t>(rows));
  EXPECT_NEAR(r->columns[17][rows - 1], 0.0125 + 1.7e-3 + 1e-7 * (rows - 1), 1e-11);
  EXPECT_EQ(r->dropped_rows, 0);
  std::printf("parsed %d rows x 19 columns (%zu bytes) in %.3f s\n", rows, csv.size(), s);
}

// One rate within 1% of the first recording's interval (a clock's drift), not beyond.
TEST(SameRateTest, WithinOnePercentOfTheFirstIsOneRate) {
  EXPECT_TRUE(SameRate(0.01, 0.01));
  EXPECT_TRUE(SameRate(0.01005, 0.01));
  EXPECT_FALSE(SameRate(0.02, 0.01));
  EXPECT_FALSE(SameRate(0.0098, 0.01));
}

}  // namespace
}  // namespace gaitforge::recording
