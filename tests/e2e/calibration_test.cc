// The calibration study end to end: recordings made by the model with known parameters,
// uploaded through the API, fitted by CMA-ES on real workers that fetch them by hash, and
// reported with held-out error.
#include <gtest/gtest.h>

#include <tuple>
#include <sqlite3.h>

#include <cmath>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

// Three gaits: an evolved one (moves forward by hopping) and two hand-made ones.
const char* kGaitA =
    "0.066346016790415963,0.92228296711382263,0.99884798501519678,0.91495911032617716,"
    "0.013764065590901597,0.027395295966066602,0.32783986902260742,0.36116692841980558,"
    "0.1062628441354091,0.40778045503790639,0.36272688662110386,0.30411357539492101,"
    "0.35444634996911673";
const char* kGaitB = "0.05,0.2,0.35,0.3,0.45,0.6,0.45,0.6,0.75,0.7,0.85,0.0,0.5";
const char* kGaitC = "0.0,0.1,0.2,0.5,0.6,0.7,0.3,0.4,0.5,0.8,0.9,0.0,0.7";
// The truth the recordings are made with; caterpillar.yaml says 8.8 N and scale 1.
const char* kTruth = "actuators.force_n=9.6,scale.link_stiffness=1.15";

double JsonNumber(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern + R"(\s*([-0-9.eE+]+))"))) return NAN;
  return std::stod(m[1]);
}

// csv with every cell replaced by f(line, column, cell), both counted from 0 (line 0 is the
// header, column 0 is t).
std::string MapCells(const std::string& csv,
                     const std::function<std::string(int, int, const std::string&)>& f) {
  std::istringstream rows(csv);
  std::string out, row;
  for (int line = 0; std::getline(rows, row); ++line) {
    std::istringstream split(row);
    int col = 0;
    for (std::string cell; std::getline(split, cell, ','); ++col)
      out += (col ? "," : "") + f(line, col, cell);
    out += "\n";
  }
  return out;
}

// validate --from-calibration: a study's gaits predicted by a calibration's model. On the
// calibration the study came from (`study` of calibration `cal`, with gait.yaml its spec)
// that is its own validation, bit for bit; on a study of the default model, the
// calibration's values replace the model's.
void ExpectValidationFromCalibration(const std::string& cli, TempDir& dir, const std::string& cal,
                                     const std::string& study) {
  auto means = [](const std::string& json) {
    std::vector<std::string> out;
    const std::regex mean(R"re("mean": ([^,}]+))re");
    for (auto it = std::sregex_iterator(json.begin(), json.end(), mean); it != std::sregex_iterator(); ++it)
      out.push_back((*it)[1]);
    return out;
  };
  const std::string validate = cli + "validate " + study + " --top 2 --json --members 3";
  auto own = RunCommand(validate);
  auto rebased = RunCommand(validate + " --from-calibration " + cal);
  ASSERT_EQ(own.exit_code, 0) << own.err;
  ASSERT_EQ(rebased.exit_code, 0) << rebased.err;
  EXPECT_EQ(means(own.out).size(), 2u) << own.out;
  EXPECT_EQ(means(rebased.out), means(own.out)) << rebased.out;
  EXPECT_NE(rebased.out.find("\"from_calibration\": \"" + cal + "\""), std::string::npos);
  WriteFile(dir.File("plain.yaml"),
            std::regex_replace(std::regex_replace(ReadFile(dir.File("gait.yaml")),
                                                  std::regex("  from_calibration: .*\n"), ""),
                               std::regex("name: from-calib"), "name: plain"));
  ASSERT_EQ(RunCommand(cli + "local plain.yaml --workers 2 --dashboard off").exit_code, 0);
  std::smatch p;
  const std::string listed = RunCommand(cli + "list --json").out;
  ASSERT_TRUE(std::regex_search(listed, p, std::regex(R"re("study_id":\s*"(plain[^"]*)")re"))) << listed;
  const std::string plain = cli + "validate " + p[1].str() + " --top 2 --json --members 3";
  auto plain_own = RunCommand(plain), plain_cal = RunCommand(plain + " --from-calibration " + cal);
  ASSERT_EQ(plain_cal.exit_code, 0) << plain_cal.err;
  EXPECT_NE(means(plain_cal.out), means(plain_own.out)) << plain_cal.out;
  std::smatch v;
  ASSERT_TRUE(std::regex_search(plain_cal.out, v, std::regex(R"re("validation_study_id": "([^"]+)")re")));
  EXPECT_TRUE(std::regex_search(RunCommand(cli + "show " + v[1].str() + " --json").out,
                                std::regex(R"re("set":\s*"actuators.force_n=[0-9.]+,scale.link_stiffness=[0-9.]+")re")));
}

TEST(Calibration, RecoversKnownParametersAndImprovesTheFit) {
  TempDir dir;
  const std::string sim = Bin("gaitforge-sim");
  for (const auto& [name, gait, cycles] :
       std::vector<std::tuple<std::string, std::string, int>>{
           {"a.csv", kGaitA, 12}, {"b.csv", kGaitB, 10}, {"c.csv", kGaitC, 10}}) {
    auto r = RunCommand(sim + " trajectory --robot caterpillar --genes " + gait + " --cycles " +
                        std::to_string(cycles) + " --set " + kTruth + " --out " + dir.File(name));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  WriteFile(dir.File("bad.csv"), "t,m1.x\n0.0,0.1\n0.01,abc\n");
  WriteFile(dir.File("bad.csv.json"), ReadFile(dir.File("a.csv.json")));

  WriteFile(dir.File("calib.yaml"), R"(name: calib
seed: 11
engine: cmaes
population: 8
generations: 100
objective:
  name: caterpillar.calibration
  options: {error: shape, metric: rmse}
  recordings: [a.csv, b.csv]
  held_out: [c.csv]
bounds:
  - {name: actuators.force_n, lo: 7.0, hi: 11.0}
  - {name: scale.link_stiffness, lo: 0.7, hi: 1.4}
cmaes:
  mean0: [8.8, 1.0]
  sigma0: 0.25
  restarts: none
  max_evaluations: 480
)");
  auto run = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") +
                        " local calib.yaml --workers 2 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " ";
  auto list = RunCommand(cli + "recording list --json");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  // The three recordings the spec named by file, stored once each by content hash.
  const std::regex hash_key("\"hash\"");
  const auto hashes = std::distance(
      std::sregex_iterator(list.out.begin(), list.out.end(), hash_key), std::sregex_iterator());
  EXPECT_EQ(hashes, 3) << list.out;
  EXPECT_NE(list.out.find("a.csv"), std::string::npos);
  EXPECT_NE(list.out.find("c.csv"), std::string::npos);
  // A broken recording is refused with its file, line and column.
  auto bad = RunCommand(cli + "recording add bad.csv");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("bad.csv:3:2"), std::string::npos) << bad.err;
  // Occluded markers (empty and NaN cells) upload, bridged and counted: the third data row's
  // m1.x empty, the fourth's m2.z NaN.
  const std::string occluded =
      MapCells(ReadFile(dir.File("c.csv")), [](int line, int col, const std::string& cell) {
        if (line == 3 && col == 1) return std::string();  // m1.x
        if (line == 4 && col == 6) return std::string("NaN");  // m2.z
        return cell;
      });
  WriteFile(dir.File("occluded.csv"), occluded);
  WriteFile(dir.File("occluded.csv.json"), ReadFile(dir.File("c.csv.json")));
  auto occ = RunCommand(cli + "recording add occluded.csv --json");
  EXPECT_EQ(occ.exit_code, 0) << occ.err;
  EXPECT_NE(occ.out.find("\"missing_cells\":\"2\""), std::string::npos) << occ.out;
  auto occ_text = RunCommand(cli + "recording add occluded.csv");
  EXPECT_EQ(occ_text.exit_code, 0) << occ_text.err;
  EXPECT_NE(occ_text.err.find("2 empty or NaN cells bridged"), std::string::npos) << occ_text.err;
  // The same recording exported in millimetres is refused before anything calibrates
  // against it, at the column that gave it away, with the factor.
  const std::string millimetres =
      MapCells(ReadFile(dir.File("c.csv")), [](int line, int col, const std::string& cell) {
        return line == 0 || col == 0 ? cell : std::to_string(1000 * std::stod(cell));
      });
  WriteFile(dir.File("mm.csv"), millimetres);
  WriteFile(dir.File("mm.csv.json"), ReadFile(dir.File("c.csv.json")));
  auto mm = RunCommand(cli + "recording add mm.csv");
  EXPECT_EQ(mm.exit_code, 2) << mm.err;
  EXPECT_NE(mm.err.find("mm.csv:1:5: neighbouring markers are"), std::string::npos) << mm.err;
  EXPECT_NE(mm.err.find("look like millimetres (divide every position by 1000)"),
            std::string::npos)
      << mm.err;

  // The fit: within the stated tolerance of the truth (force 0.3 N, stiffness scale 0.1).
  // The robot hops, so the error landscape is rugged at small scales
  // (../shared/robots/caterpillar.md); these tolerances sit above that floor.
  const std::string id = std::regex_replace(
      RunCommand(cli + "list --json").out, std::regex(R"re([\s\S]*"study_id":"([^"]+)"[\s\S]*)re"),
      "$1");
  auto hof = RunCommand(cli + "hof " + id + " --json");
  ASSERT_EQ(hof.exit_code, 0) << hof.err;
  std::smatch genes;
  ASSERT_TRUE(std::regex_search(hof.out, genes,
                                std::regex(R"("genes":\[([-0-9.eE+]+),([-0-9.eE+]+)\])")))
      << hof.out;
  EXPECT_NEAR(std::stod(genes[1]), 9.6, 0.3) << hof.out;
  EXPECT_NEAR(std::stod(genes[2]), 1.15, 0.1) << hof.out;
  EXPECT_TRUE(std::regex_search(hof.out, std::regex(R"re("spread":\[[0-9.eE+-]+,[0-9.eE+-]+\])re")))
      << "an uncertainty per parameter: " << hof.out;

  // The report: training error at least halved; held-out error not worse beyond the hop's
  // chaotic floor (the parameters sit within the tolerances above, yet a hop's timing off by
  // a few ms moves the held-out error by a few percent either way).
  const std::string report = ReadFile(dir.File("runs/plots/" + id + "-calibration.json"));
  ASSERT_FALSE(report.empty());
  auto error_of = [&](const std::string& section) {
    const size_t at = report.find("\"" + section + "\"");
    return JsonNumber(report.substr(at), R"("error":)");
  };
  EXPECT_LT(error_of("train_after"), 0.5 * error_of("train_before"));
  EXPECT_LE(error_of("held_out_after"), error_of("held_out_before") * 1.05);
  for (const char* f : {"-overlays.svg", "-errors.svg", "-distance-ratio.svg"})
    EXPECT_NE(ReadFile(dir.File("runs/plots/" + id + f)).find("<svg"), std::string::npos) << f;

  // Closing the loop from the calibration: a robust gait study on the fitted model, its
  // ensemble over the fit's spread, predicting with an interval.
  WriteFile(dir.File("gait.yaml"), "name: from-calib\nseed: 1\npopulation: 6\ngenerations: 2\n"
                                   "ga: {elite: 2}\nobjective:\n  name: caterpillar.distance\n"
                                   "  from_calibration: " + id +
                                       "\n  params: {cycles: 1, settle_cycles: 1}\n"
                                       "  robust: {members: 3}\n");
  auto gait = RunCommand(cli + "local gait.yaml --workers 2 --dashboard off");
  ASSERT_EQ(gait.exit_code, 0) << gait.err;
  std::smatch m;
  const std::string studies = RunCommand(cli + "list --json").out;
  ASSERT_TRUE(std::regex_search(studies, m, std::regex(R"re("study_id":\s*"(from-calib[^"]*)")re")))
      << studies;
  const std::string show = RunCommand(cli + "show " + m[1].str() + " --json").out;
  EXPECT_TRUE(std::regex_search(show, std::regex(R"re("set":\s*"actuators.force_n=[0-9.]+,scale.link_stiffness=[0-9.]+")re")))
      << show;
  EXPECT_TRUE(std::regex_search(show, std::regex(R"re("parameters":\s*\[\s*\{\s*"name":\s*"actuators.force_n",\s*"lo")re")))
      << show;
  EXPECT_EQ(show.find("nuisance.time_offset_s="), std::string::npos) << show;
  EXPECT_NE(RunCommand(cli + "hof " + m[1].str()).out.find("PREDICTED [MIN, MAX]"), std::string::npos);
  // sampling: fits: each member's force and stiffness are one evaluation of the calibration
  // that fits both recordings as well as its best, as a pair.
  WriteFile(dir.File("fits.yaml"),
            std::regex_replace(std::regex_replace(ReadFile(dir.File("gait.yaml")),
                                                  std::regex("robust: \\{members: 3\\}"),
                                                  "robust: {members: 3, sampling: fits}"),
                               std::regex("name: from-calib"), "name: from-fits"));
  auto fits = RunCommand(cli + "local fits.yaml --workers 2 --dashboard off");
  ASSERT_EQ(fits.exit_code, 0) << fits.err;
  const std::string all = RunCommand(cli + "list --json").out;
  std::smatch f;
  ASSERT_TRUE(std::regex_search(all, f, std::regex(R"re("study_id":\s*"(from-fits[^"]*)")re"))) << all;
  const std::string fits_show = RunCommand(cli + "show " + f[1].str() + " --json").out;
  EXPECT_TRUE(std::regex_search(
      fits_show, std::regex(R"re("samples":\s*\[\s*\{\s*"values":\s*\[\s*[0-9.]+,\s*[0-9.]+\s*\]\s*\})re")))
      << fits_show;
  EXPECT_EQ(fits_show.find("nuisance.time_offset_s"), std::string::npos) << fits_show;
  ExpectValidationFromCalibration(cli, dir, id, m[1].str());
  // A study that is no calibration is refused, naming the field.
  WriteFile(dir.File("bad-gait.yaml"), std::regex_replace(ReadFile(dir.File("gait.yaml")),
                                                          std::regex("from_calibration: .*"),
                                                          "from_calibration: " + m[1].str()));
  auto bad_gait = RunCommand(cli + "local bad-gait.yaml --workers 1 --dashboard off");
  EXPECT_NE(bad_gait.exit_code, 0);
  EXPECT_NE(bad_gait.err.find("objective.from_calibration: study " + m[1].str() +
                              " is a caterpillar.distance study, not a calibration"),
            std::string::npos)
      << bad_gait.err;
}

// A diagnosis spec with a bad field is refused before anything runs: exit 2, the file and
// the field named, with what it allows.
TEST(Diagnose, RefusesBadSpecsNamingTheField) {
  TempDir dir;
  const std::string head = "name: d\nrobot: caterpillar\ntraining: [a.csv]\nheld_out: [c.csv]\n";
  for (const auto& [extra, expected] : std::vector<std::pair<std::string, std::string>>{
           {"weighting: both\n", "field 'weighting': 'both' is not one of equal, floor, pooled"},
           {"error: wiggle\n", "field 'error': one of shape, pointwise, stats, acceleration"},
           {"params: {window: 1}\n", "field 'params.window': not a param of the comparison"},
           {"params: {max_shift_samples: 2.5}\n",
            "field 'params.max_shift_samples': 2.5 is out of range [0, 1000], whole"},
           {"top: 0\n", "field 'top': out of range [1, 20]"},
           {"screening_tie: 0.5\n", "field 'screening_tie': out of range [0, 0.2]"},
           {"candidates: [ground.wobble]\n", "field 'candidates[0]': 'ground.wobble'"}}) {
    WriteFile(dir.File("d.yaml"), head + extra);
    auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " diagnose d.yaml");
    EXPECT_EQ(r.exit_code, 2) << extra << r.err;
    EXPECT_NE(r.err.find("d.yaml"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
}

// A spec that names no robot diagnoses the robot its first training recording names (the
// interrupted diagnosis below runs so); a recording naming an unknown robot is refused
// before anything runs, naming its sidecar.
TEST(Diagnose, ASpecWithoutARobotTakesItFromItsRecordingOrSaysWhy) {
  TempDir dir;
  WriteFile(dir.File("a.csv"), "t,m1.x\n0,0\n0.01,0\n");
  WriteFile(dir.File("a.csv.json"), "{\"robot\": \"blimp\", \"command\": {\"kind\": \"gait\", "
                                    "\"genes\": [0.5]}}\n");
  WriteFile(dir.File("d.yaml"), "name: d\ntraining: [a.csv]\nheld_out: [a.csv]\n");
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " diagnose d.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("field 'robot' is left out"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a.csv.json:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("blimp"), std::string::npos) << r.err;
}

// One spec diagnoses one robot from recordings at one rate: a recording of another robot,
// or at another rate, is refused before anything runs, naming its field.
TEST(Diagnose, RecordingsOfAnotherRobotOrRateAreRefused) {
  TempDir dir;
  for (const auto& [name, robot, genes, rate] :
       {std::make_tuple("a.csv", "walker", "2,0.4,0,0.1", "50"),
        std::make_tuple("b.csv", "walker", "1.5,0.3,0.1,0.05", "50"),
        std::make_tuple("c.csv", "walker", "1.5,0.3,0.1,0.05", "100"),
        std::make_tuple("t.csv", "tigrillo", "1,0.35,0.35,0.1,0.1,0.5,0.25,5", "50")}) {
    auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --robot " + robot + " --genes " +
                        genes + " --cycles 1 --settle 0 --rate " + rate + " --out " +
                        dir.File(name));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  WriteFile(dir.File("robot.yaml"), "name: d\ntraining: [a.csv, t.csv]\nheld_out: [b.csv]\n");
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " diagnose robot.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("field 'training[1]': recording 't.csv' is of robot 'tigrillo'"),
            std::string::npos) << r.err;
  WriteFile(dir.File("rate.yaml"), "name: d\ntraining: [a.csv]\nheld_out: [c.csv]\n");
  r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " diagnose rate.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("field 'held_out[0]': recording 'c.csv' is sampled every 0.01 s"),
            std::string::npos) << r.err;
}

// A diagnosis interrupted by kill -9 and run again reuses the fits already in its database
// (same spec and seed: same result), creates no duplicate study, and reaches exactly the
// report of an uninterrupted run.
TEST(Diagnose, AnInterruptedDiagnosisRunAgainReusesItsFitsAndEndsTheSame) {
  TempDir dir;
  const std::string cases =
      std::string(GAITFORGE_SOURCE_DIR) + "/tests/diagnosis/cases/tether-hose/";
  WriteFile(dir.File("d.yaml"), "name: mini\nseed: 3\ntraining: [" + cases + "train/gait-a.csv, " +
                                    cases + "train/gait-b.csv]\nheld_out: [" + cases +
                                    "held_out/gait-c.csv]\ncandidates: [tether.constant, "
                                    "ground.slope]\nscreening_evaluations: 16\n"
                                    "full_evaluations: 24\ntop: 2\n");
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge");
  auto whole = RunCommand(cli + " --db whole.db --out whole diagnose d.yaml --json --workers 2");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  RunCommand("cd " + dir.path() + " && { " + Bin("gaitforge") +
             " --db " + dir.File("cut.db") +
             " --out cut diagnose d.yaml --json --workers 2 > cut.out 2> cut.err & "
             "echo $! > cut.pid; }");
  const std::string pid = std::to_string(std::stoi(ReadFile(dir.File("cut.pid"))));
  bool some_done = false;
  for (int i = 0; i < 1200 && !some_done; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    some_done = RunCommand(cli + " --db cut.db list --json").out.find("STUDY_STATE_COMPLETED") !=
                std::string::npos;
  }
  ASSERT_TRUE(some_done) << ReadFile(dir.File("cut.err"));
  ASSERT_EQ(RunCommand("kill -9 " + pid).exit_code, 0);
  EXPECT_TRUE(ReadFile(dir.File("cut.out")).empty()) << "it had finished before the kill";
  // Its private coordinator gets SIGTERM when it dies and releases the database as it
  // stops; wait for that (the pattern in a file, so the shell running pgrep does not match).
  WriteFile(dir.File("cut.re"), "--db " + dir.File("cut.db"));
  for (int i = 0; i < 600; ++i) {
    if (RunCommand("pgrep -f -- \"$(cat " + dir.File("cut.re") + ")\"").out.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  auto again = RunCommand(cli + " --db cut.db --out cut diagnose d.yaml --json --workers 2");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_GE(JsonNumber(again.out, R"("reused_fits":)"), 1) << again.out;
  EXPECT_EQ(JsonNumber(whole.out, R"("reused_fits":)"), 0) << whole.out;
  // The verdict, effects, errors, runners-up and screening, byte for byte (but the ids of
  // the fits' studies, which each database draws its own).
  auto report = [](const std::string& out) {
    const size_t from = out.find("\"verdict\"");
    return std::regex_replace(out.substr(from, out.find("\"refitted_singles\"") - from),
                              std::regex(R"("study_id": "[^"]*")"), "");
  };
  EXPECT_EQ(report(again.out), report(whole.out));
  auto studies = [&](const std::string& db) {
    const std::string out = RunCommand(cli + " --db " + db + " list --json").out;
    int n = 0;
    for (size_t at = out.find("\"study_id\""); at != std::string::npos;
         at = out.find("\"study_id\"", at + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(studies("cut.db"), studies("whole.db"));  // no fit was run twice

  // The corrected model is ready for new gait studies: its objective section runs as one,
  // and the hose it adds makes the same first generation of gaits travel less far.
  ASSERT_NE(whole.out.find(R"("verdict": "found", "effects": [{"id": "tether.constant")"),
            std::string::npos)
      << whole.out;
  // Its magnitude comes with the range the training data cannot tell from it (the same in
  // the interrupted run: compared above), around the fitted value and not a point.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      whole.out, m,
      std::regex(R"re("effect.tether_force_n": \{"index": 0, "value": ([-0-9.e]+), "sd": [-0-9.enul]+, "lo": 0, "hi": 2.5, "range": \[([-0-9.e]+), ([-0-9.e]+)\], "range_share": ([-0-9.e]+)\})re")))
      << whole.out;
  const double value = std::stod(m[1]), lo = std::stod(m[2]), hi = std::stod(m[3]);
  EXPECT_LE(lo, value);
  EXPECT_GE(hi, value);
  EXPECT_LT(lo, hi);
  // Named, so required and pinned: the range leaves out 0 N (no hose), and spans a small
  // share of the allowed 0 .. 2.5 N.
  EXPECT_GT(lo, 0);
  EXPECT_NEAR(std::stod(m[4]), (hi - lo) / 2.5, 1e-4);
  EXPECT_LT(std::stod(m[4]), 0.9);
  EXPECT_GT(JsonNumber(whole.out, R"("range_accepted":)"), 1) << whole.out;
  // Where it showed, against the model's own spread: the hose's training recordings are
  // beyond the six numeric variants' spread (gait B travels about 12 sd short), so the
  // report located it, and a found verdict leaves nothing unexplained.
  EXPECT_NE(whole.out.find(R"("unexplained_mismatch": false)"), std::string::npos) << whole.out;
  const size_t located = whole.out.find(R"("located": {)");
  const size_t held = whole.out.find(R"("located_held_out": {)");
  ASSERT_NE(located, std::string::npos) << whole.out;
  ASSERT_NE(held, std::string::npos) << whole.out;
  const std::string training = whole.out.substr(located, held - located);
  EXPECT_NE(training.find(R"("variants": 6)"), std::string::npos) << training;
  EXPECT_NE(training.find(R"("beyond_spread": true)"), std::string::npos) << training;
  // The held-out recordings too, from the evaluations the noise floor made.
  const std::string held_out =
      whole.out.substr(held, whole.out.find(R"("experiment")", held) - held);
  EXPECT_NE(held_out.find(R"("variants": 6)"), std::string::npos) << held_out;
  const std::string corrected = ReadFile(dir.File("whole/mini-diagnosis/corrected-model.yaml"));
  ASSERT_NE(corrected.find("effect.tether_force_n="), std::string::npos) << corrected;
  const std::string gaits = "seed: 5\npopulation: 12\ngenerations: 1\n";
  WriteFile(dir.File("with.yaml"), "name: with-hose\n" + gaits + corrected);
  WriteFile(dir.File("without.yaml"),
            "name: without\n" + gaits + "objective:\n  name: caterpillar.distance\n");
  LocalCluster cluster(dir.path(), dir.File("gaits.db"));
  ASSERT_TRUE(cluster.ok());
  cluster.StartWorkers(2);
  auto best = [&](const std::string& spec) {
    auto submit = cluster.Cli("submit " + dir.File(spec));
    EXPECT_EQ(submit.exit_code, 0) << submit.err;
    const std::string id = submit.out.substr(0, submit.out.find('\n'));
    EXPECT_EQ(cluster.Cli("watch " + id).exit_code, 0);
    return JsonNumber(cluster.Cli("show " + id + " --json").out, R"("best_fitness":)");
  };
  EXPECT_LT(best("with.yaml"), best("without.yaml"));
}

}  // namespace
}  // namespace gaitforge::testing
