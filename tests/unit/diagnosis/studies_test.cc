// The gap finder's fits as studies (services/diagnosis/studies.h), on a coordinator held in
// memory: which studies are created, which reused, what a fit reads back, and stopping.
#include "services/diagnosis/studies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include "absl/strings/str_join.h"
#include "robots/count_override.h"
#include "robots/registry.h"

#include "services/diagnosis/fits.h"
#include "services/diagnosis/spec.h"
#include "services/spec/spec_validation.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

// Studies finish as soon as they are created, with a best member whose fitness is -error.
class MemoryStudies : public Studies {
 public:
  std::map<std::string, v1::StudySummary> studies;
  int created = 0;
  bool finish = true;
  double error = 0.002;
  absl::StatusOr<std::vector<v1::StudySummary>> List() override {
    std::vector<v1::StudySummary> out;
    for (const auto& [id, s] : studies) out.push_back(s);
    return out;
  }
  absl::StatusOr<std::string> Create(const v1::StudySpec& spec) override {
    v1::StudySummary s;
    s.set_study_id("s" + std::to_string(++created));
    *s.mutable_spec() = spec;
    spec::ApplyDefaults(s.mutable_spec());
    s.set_state(finish ? v1::STUDY_STATE_COMPLETED : v1::STUDY_STATE_RUNNING);
    studies[s.study_id()] = s;
    return s.study_id();
  }
  absl::StatusOr<v1::StudySummary> Get(const std::string& id) override { return studies.at(id); }
  absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string& id) override {
    v1::GetHallOfFameResponse r;
    auto* ind = r.add_entries()->mutable_individual();
    for (int i = 0; i < studies.at(id).spec().bounds_size(); ++i) ind->add_genes(0.1 * (i + 1));
    ind->mutable_evaluation()->set_valid(true);
    ind->mutable_evaluation()->set_fitness(-error);
    return r;
  }
};

v1::DiagnosisSpec Spec() {
  v1::DiagnosisSpec d;
  d.set_name("t");
  d.set_robot("caterpillar");
  d.add_training("a");
  d.add_held_out("c");
  Defaults(&d);
  return d;
}

TEST(RunFits, CreatesOneCalibrationStudyPerCandidateAndReadsItsBestFit) {
  MemoryStudies studies;
  const v1::DiagnosisSpec d = Spec();
  Candidate base = Make(d, {}), tether = Make(d, {"tether.constant"});
  int reused = 0;
  ASSERT_TRUE(RunFits(studies, d, {&base, &tether}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s",
                      &reused)
                  .ok());
  EXPECT_EQ(studies.created, 2);
  EXPECT_EQ(reused, 0);
  const auto& spec = studies.studies.at(tether.study_id).spec();
  EXPECT_EQ(spec.objective().name(), "caterpillar.calibration");
  EXPECT_EQ(spec.objective().recordings(0), "a");
  EXPECT_EQ(spec.objective().held_out(0), "c");
  EXPECT_EQ(spec.bounds(0).name(), "effect.tether_force_n");
  EXPECT_TRUE(tether.ok);
  EXPECT_DOUBLE_EQ(tether.train, 0.002);
  ASSERT_EQ(tether.values.size(), tether.genes.size());
}

TEST(RunFits, ReusesAStudyWithTheSameSpecAndSeed) {
  MemoryStudies studies;
  const v1::DiagnosisSpec d = Spec();
  Candidate a = Make(d, {"ground.slope"}), b = Make(d, {"ground.slope"});
  int reused = 0;
  ASSERT_TRUE(RunFits(studies, d, {&a}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  ASSERT_TRUE(RunFits(studies, d, {&b}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  EXPECT_EQ(studies.created, 1);
  EXPECT_EQ(reused, 1);
  EXPECT_EQ(a.study_id, b.study_id);
  // Another budget is another study.
  Candidate c = Make(d, {"ground.slope"});
  ASSERT_TRUE(RunFits(studies, d, {&c}, 48, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  EXPECT_EQ(studies.created, 2);
}

TEST(RunFits, AFitWithoutAValidMemberIsNotOkAndSaysWhy) {
  const v1::DiagnosisSpec d = Spec();
  Candidate a = Make(d, {});
  int reused = 0;
  class NoValid : public MemoryStudies {
    absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string&) override {
      return v1::GetHallOfFameResponse();
    }
  } none;
  ASSERT_TRUE(RunFits(none, d, {&a}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  EXPECT_FALSE(a.ok);
  EXPECT_EQ(a.reason, "no valid fit");
}

TEST(RunFits, StopsWhenTheReporterSaysSoAndReportsProgress) {
  MemoryStudies studies;
  studies.finish = false;
  const v1::DiagnosisSpec d = Spec();
  Candidate a = Make(d, {});
  int reused = 0, reports = 0;
  Reporter r;
  r.stopped = [] { return true; };
  r.progress = [&](const Reporter::Progress& p) {
    ++reports;
    EXPECT_EQ(p.stage, "baseline");
    EXPECT_EQ(p.fits, 1);
    EXPECT_EQ(p.fits_done, 0);
  };
  const absl::Status s = RunFits(studies, d, {&a}, 24, {{"a"}, {"c"}, ""}, r, "baseline", &reused);
  EXPECT_EQ(s.code(), absl::StatusCode::kCancelled);
  EXPECT_EQ(reports, 1);
}

// No robot is assumed: a spec without one (whose recordings did not give one either) is
// refused saying where the robot comes from.
TEST(DiagnosisSpec, ASpecWithoutARobotIsRefusedSayingWhereItComesFrom) {
  v1::DiagnosisSpec d = Spec();
  d.clear_robot();
  d.clear_candidates();
  Defaults(&d);
  EXPECT_TRUE(d.robot().empty());
  EXPECT_EQ(d.candidates_size(), 0);
  const absl::Status s = Validate(d);
  EXPECT_NE(s.message().find("field 'robot': required"), std::string::npos) << s;
  EXPECT_NE(s.message().find("first training recording"), std::string::npos) << s;
}

TEST(DiagnosisSpec, AHeldOutRecordingThatIsAlsoATrainingOneIsRefused) {
  v1::DiagnosisSpec d = Spec();
  Defaults(&d);
  ASSERT_TRUE(Validate(d).ok());
  d.add_held_out(d.training(0));
  const absl::Status s = Validate(d);
  EXPECT_NE(s.message().find("field 'held_out[1]'"), std::string::npos) << s;
  EXPECT_NE(s.message().find("is also training[0]"), std::string::npos) << s;
}

// Defaults fills in every effect that applies; a spec left with none would fit a baseline
// and name nothing, which reads as "no missing physics": refused, naming the field.
TEST(DiagnosisSpec, ASpecWithNoCandidateLeftIsRefused) {
  v1::DiagnosisSpec d = Spec();
  Defaults(&d);
  ASSERT_GT(d.candidates_size(), 0);
  d.clear_candidates();
  const absl::Status s = Validate(d);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << s;
  EXPECT_NE(s.message().find("field 'candidates': none to fit"), std::string::npos) << s;
}

TEST(DiagnosisSpec, ARobotWithoutACalibrationObjectiveIsRefusedNamingTheKnownOnes) {
  v1::DiagnosisSpec d = Spec();
  d.set_robot("twobox");
  const absl::Status s = Validate(d);
  EXPECT_NE(s.message().find("field 'robot': 'twobox'"), std::string::npos) << s;
  // Every built-in robot is diagnosable: the caterpillar by its own calibration, the others
  // on the generic builder.
  EXPECT_NE(s.message().find("built in: " + absl::StrJoin(robots::RobotNames(), ", ") +
                             "; or a descriptor file"),
            std::string::npos)
      << s;
}

// The caution a report gives when a numeric variant fits the recordings much better than
// the model's own numerics (the walker's null-1: 0.5 ms halves the error of 1 ms).
TEST(NumericsNote, CautionsOnlyWhenAVariantCutsTheErrorBeyondTheShare) {
  const std::vector<std::string> variants = {"", "simulation.timestep_s=0.0005",
                                             "ground.contact_cfm=3e-5"};
  const std::string note = NumericsNote(variants, {0.0033, 0.0018, 0.0031});
  EXPECT_NE(note.find("not converged"), std::string::npos) << note;
  EXPECT_NE(note.find("with simulation.timestep_s=0.0005"), std::string::npos) << note;
  EXPECT_NE(note.find("1.8 mm instead of 3.3 mm (-45%)"), std::string::npos) << note;
  EXPECT_EQ(NumericsNote(variants, {0.0033, 0.0029, 0.0031}), "");  // within 20%
  EXPECT_EQ(NumericsNote(variants, {}), "");                        // not measured
  EXPECT_EQ(NumericsNote(variants, {0.0033, 0.0018}), "");          // does not match
}

// Numerics first: the finer timestep variant that cuts the uncalibrated model's training
// error beyond the share is chosen; the variants then scale with the diagnosis's step, and
// every evaluation and fit study runs at it.
TEST(NumericsFirst, ChoosesAFinerStepAndTheWholeDiagnosisMovesToIt) {
  const std::vector<std::string> variants = {"", "simulation.timestep_s=0.0005",
                                             "simulation.timestep_s=0.00075",
                                             "simulation.timestep_s=0.00125",
                                             "ground.contact_cfm=3e-5"};
  EXPECT_DOUBLE_EQ(FinerStepMs(variants, {4.4e-3, 2.4e-3, 3.0e-3, 1e-3, 1e-4}, 1.0), 0.5);
  // A coarser step or a contact variant never counts; within the share, none.
  EXPECT_EQ(FinerStepMs(variants, {4.4e-3, 4.0e-3, 3.9e-3, 1e-3, 1e-4}, 1.0), -1);
  EXPECT_EQ(FinerStepMs(variants, {}, 1.0), -1);
  // The finest-step variant a pair must also win at (decision.h, DecisionRule::finest_step).
  EXPECT_EQ(FinestStepVariant(variants), 1);
  EXPECT_EQ(FinestStepVariant({"", "simulation.timestep_s=0.00125", "simulation.timestep_s=0.00025"}), 2);
  EXPECT_EQ(FinestStepVariant({"", "ground.contact_cfm=3e-5"}), -1);

  v1::DiagnosisSpec d = Spec();
  EXPECT_EQ(d.numerics(), "off");
  EXPECT_EQ(BaseSet(d, "ground.contact_cfm=3e-5"), "ground.contact_cfm=3e-5");
  d.set_timestep_ms(0.5);
  const std::vector<std::string> scaled = NumericVariants(d);
  ASSERT_GE(scaled.size(), 4u);
  EXPECT_EQ(scaled[0], "");
  EXPECT_EQ(scaled[1], "simulation.timestep_s=0.00025");
  EXPECT_EQ(scaled[3], "simulation.timestep_s=0.000625");
  EXPECT_EQ(BaseSet(d, ""), "simulation.timestep_s=0.0005");
  EXPECT_EQ(BaseSet(d, "ground.contact_cfm=3e-5"),
            "simulation.timestep_s=0.0005,ground.contact_cfm=3e-5");
  EXPECT_EQ(BaseSet(d, scaled[1]), scaled[1]);  // a variant's own step wins
  MemoryStudies studies;
  Candidate base = Make(d, {});
  int reused = 0;
  ASSERT_TRUE(RunFits(studies, d, {&base}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  EXPECT_DOUBLE_EQ(studies.studies.at(base.study_id).spec().objective().params().at("timestep_ms"),
                   0.5);
  d.set_numerics("sometimes");
  EXPECT_NE(Validate(d).message().find("field 'numerics': 'sometimes'"), std::string::npos);
  d.set_numerics("first");
  d.set_timestep_ms(5);
  EXPECT_NE(Validate(d).message().find("field 'timestep_ms': 5 is out of range [0.05, 2] ms"),
            std::string::npos)
      << Validate(d);
  // A step whose numeric variants (up to 1.25 times it) leave the robot's range is refused
  // before any fit, with the steps that are allowed.
  d.set_timestep_ms(2);
  EXPECT_NE(Validate(d).message().find(
                "field 'timestep_ms': 2 ms puts the numeric variants' steps at 1 to 2.5 ms, "
                "outside caterpillar's simulation.timestep_s range [0.05, 2] ms; allowed here: "
                "0.1 to 1.6 ms"),
            std::string::npos)
      << Validate(d);
  d.set_timestep_ms(1.6);
  EXPECT_TRUE(Validate(d).ok()) << Validate(d);
}

// An effect whose parameter is a base parameter would be fitted twice: the default
// candidates leave it out, and a spec that lists it is refused naming both fields.
TEST(DiagnosisSpec, ACandidateThatFitsABaseParameterIsLeftOutOrRefused) {
  v1::DiagnosisSpec d = Spec();
  d.clear_candidates();
  auto* b = d.add_base_parameters();
  b->set_name("effect.friction_forward");
  b->set_lo(0);
  b->set_hi(3);
  Defaults(&d);
  ASSERT_GT(d.candidates_size(), 3);
  for (const auto& c : d.candidates()) EXPECT_NE(c, "friction.anisotropic");
  ASSERT_TRUE(Validate(d).ok()) << Validate(d);
  d.add_candidates("friction.anisotropic");
  const absl::Status s = Validate(d);
  EXPECT_NE(s.message().find("'friction.anisotropic' fits effect.friction_forward, which "
                             "base_parameters[0] fits"),
            std::string::npos)
      << s;
}

// A robot whose build rules an effect out (`ruled_out`): the default candidates leave it
// out, a spec that lists it is refused with the descriptor's reason, and an id that is no
// catalog effect is refused naming its line.
TEST(DiagnosisSpec, AnEffectTheRobotRulesOutIsNeitherTriedNorAccepted) {
  v1::DiagnosisSpec d = Spec();
  d.set_robot("walker");
  d.clear_candidates();
  Defaults(&d);
  ASSERT_GT(d.candidates_size(), 3);
  for (const auto& c : d.candidates()) EXPECT_EQ(c.rfind("tether.", 0), std::string::npos) << c;
  EXPECT_TRUE(std::count(d.candidates().begin(), d.candidates().end(), "ground.slope"));
  ASSERT_TRUE(Validate(d).ok()) << Validate(d);
  d.add_candidates("tether.constant");
  absl::Status s = Validate(d);
  EXPECT_NE(s.message().find("'tether.constant' cannot be fitted on walker: walker's descriptor "
                             "rules it out (robots/walker/robot.yaml:"),
            std::string::npos)
      << s;
  EXPECT_NE(s.message().find("battery"), std::string::npos) << s;
  std::ifstream in(std::string(GAITFORGE_SOURCE_DIR) + "/robots/walker/robot.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("  tether.growing:"), 17, "  tether.gruwing:");
  d.set_robot_descriptor(text);
  d.clear_candidates();
  d.add_candidates("ground.slope");
  s = Validate(d);
  EXPECT_NE(s.message().find(": ruled_out.tether.gruwing: 'tether.gruwing' is not an effect of the catalog"),
            std::string::npos)
      << s;
}

// Structure first: a structural fit moved into the base model fits its parameters as base
// parameters (same bounds, same order as in its own fit), and leaves the candidates; every
// later candidate then fits it too.
TEST(DiagnosisSpec, AStructureMovedIntoTheBaseIsFittedEverywhereAndNoLongerACandidate) {
  v1::DiagnosisSpec d = Spec();
  ASSERT_TRUE(std::count(d.candidates().begin(), d.candidates().end(), "friction.anisotropic"));
  const Candidate structure = Make(d, {"friction.anisotropic"});
  const v1::DiagnosisSpec moved = WithStructure(d, structure);
  ASSERT_EQ(moved.base_parameters_size(), 2);
  EXPECT_EQ(moved.base_parameters(0).name(), "effect.friction_forward");
  EXPECT_EQ(moved.base_parameters(1).name(), "effect.friction_backward");
  EXPECT_EQ(moved.base_parameters(1).hi(), 3);
  EXPECT_EQ(moved.candidates_size(), d.candidates_size() - 1);
  EXPECT_FALSE(std::count(moved.candidates().begin(), moved.candidates().end(),
                          "friction.anisotropic"));
  EXPECT_TRUE(Validate(moved).ok()) << Validate(moved);
  // The new baseline has the structure's genes in the structure's own fit's order.
  const Candidate base = Make(moved, {});
  ASSERT_EQ(base.genes.size(), structure.genes.size());
  for (size_t i = 0; i < base.genes.size(); ++i) EXPECT_EQ(base.genes[i].name(), structure.genes[i].name());
  const Candidate hose = Make(moved, {"tether.constant"});
  EXPECT_EQ(hose.genes[0].name(), "effect.friction_forward");
  EXPECT_EQ(hose.k, base.k + 1);
  EXPECT_TRUE(effects::IsStructural("friction.anisotropic"));
  EXPECT_FALSE(effects::IsStructural("tether.constant"));
}

// structure: joint moves every structural effect of one fit into the base at once.
TEST(DiagnosisSpec, AJointStructureMovesEveryOneOfItsEffectsIntoTheBase) {
  v1::DiagnosisSpec d = Spec();
  const Candidate joint = Make(d, {"contact.softness", "damping.scale", "mass.offset"});
  const v1::DiagnosisSpec moved = WithStructure(d, joint);
  ASSERT_EQ(moved.base_parameters_size(), 3);
  EXPECT_EQ(moved.base_parameters(0).name(), "ground.contact_cfm");
  EXPECT_EQ(moved.base_parameters(1).name(), "scale.link_damping");
  EXPECT_EQ(moved.base_parameters(2).name(), "scale.mass");
  EXPECT_EQ(moved.candidates_size(), d.candidates_size() - 3);
  for (const char* id : {"contact.softness", "damping.scale", "mass.offset"})
    EXPECT_FALSE(std::count(moved.candidates().begin(), moved.candidates().end(), id)) << id;
  EXPECT_TRUE(Validate(moved).ok()) << Validate(moved);
}

TEST(DiagnosisSpec, StructureIsOffByDefaultAndOneOfOffFirstOrJoint) {
  v1::DiagnosisSpec d = Spec();
  EXPECT_EQ(d.structure(), "off");
  d.set_structure("joint");
  EXPECT_TRUE(Validate(d).ok()) << Validate(d);
  d.set_structure("later");
  EXPECT_NE(Validate(d).message().find("field 'structure': 'later' is not one of off, first, joint"),
            std::string::npos)
      << Validate(d);
}

TEST(DiagnosisSpec, APairsBudgetIsHalfTheFullOneByDefaultAndAtLeastEight) {
  v1::DiagnosisSpec d = Spec();
  EXPECT_EQ(d.pair_evaluations(), d.full_evaluations() / 2);
  d.set_pair_evaluations(4);
  EXPECT_NE(Validate(d).message().find("field 'pair_evaluations': 4 is below 8"),
            std::string::npos)
      << Validate(d);
}

// A robot's own suspects (its descriptor's `suspects:`) are candidates beside the catalog's
// effects, fitted from the nominal value over the range the descriptor gives.
TEST(DiagnosisSpec, ARobotsSuspectsAreCandidatesStartingAtTheModel) {
  v1::DiagnosisSpec d = Spec();
  d.set_robot("tigrillo");
  d.clear_candidates();
  Defaults(&d);
  ASSERT_TRUE(Validate(d).ok()) << Validate(d);
  const auto& ids = d.candidates();
  EXPECT_NE(std::find(ids.begin(), ids.end(), "knee.hind_stiffness"), ids.end());
  EXPECT_NE(std::find(ids.begin(), ids.end(), "servo.deadband"), ids.end());
  EXPECT_NE(std::find(ids.begin(), ids.end(), "actuator.lag"), ids.end());
  EXPECT_EQ(std::find(ids.begin(), ids.end(), "mass.offset"), ids.end());  // no scale.mass
  const Candidate c = Make(d, {"knee.hind_stiffness"});
  ASSERT_EQ(c.genes.size(), 2u);  // the suspect's parameter and the time offset
  EXPECT_EQ(c.genes[0].name(), "knee.hind_stiffness_nm_per_rad");
  EXPECT_EQ(c.genes[0].lo(), 0.05);
  EXPECT_EQ(c.mean0[0], 0.2225);
  EXPECT_EQ(c.gene_effect[0], "knee.hind_stiffness");
  d.add_candidates("knee.front_stiffness");
  EXPECT_NE(Validate(d).message().find("or a suspect of tigrillo"), std::string::npos) << Validate(d);
}

}  // namespace
}  // namespace gaitforge::diagnosis

namespace gaitforge::diagnosis {
namespace {

// Resolution (structure first): a diagnosis moved to another resolution carries the finer
// descriptor into every fit's study, and a fit started from the baseline carries its start
// and its shorter step.
TEST(Resolution, AFitStudyCarriesTheFinerDescriptorAndTheCandidatesStart) {
  v1::DiagnosisSpec d;
  d.set_name("arm");
  d.set_robot("continuum_arm");
  d.add_training("a");
  d.add_held_out("c");
  d.set_error("acceleration");
  Defaults(&d);
  auto ten = robots::WithCount(robots::BuiltinText("continuum_arm"), "lumps", 10, "arm");
  ASSERT_TRUE(ten.ok()) << ten.status();
  d.set_robot_descriptor(*ten);
  ASSERT_EQ((*RobotOf(d))->bodies.size(), 10u);
  Candidate c = Make(d, {"joint.softening"});
  c.mean0[0] = 0.5;
  c.sigma0 = 0.1;
  MemoryStudies studies;
  int reused = 0;
  ASSERT_TRUE(RunFits(studies, d, {&c}, 24, {{"a"}, {"c"}, ""}, Reporter(), "s", &reused).ok());
  const auto& spec = studies.studies.at(c.study_id).spec();
  EXPECT_EQ(spec.objective().name(), "robot.calibration");
  EXPECT_EQ(spec.objective().robot_descriptor(), *ten);
  EXPECT_DOUBLE_EQ(spec.cmaes().sigma0(), 0.1);
  ASSERT_GE(spec.cmaes().mean0_size(), 1);
  EXPECT_DOUBLE_EQ(spec.cmaes().mean0(0), 0.5);
}

}  // namespace
}  // namespace gaitforge::diagnosis

namespace gaitforge::diagnosis {
namespace {

// A pair starts where the better of its singles' full fits ended, the other effect absent;
// the pair's own defaults (nominal values, base ranges) are kept when neither fit is ok.
TEST(StartAtBetter, APairStartsAtItsBetterSingleWithTheOtherEffectAbsent) {
  v1::DiagnosisSpec d;
  d.set_robot("caterpillar");
  d.add_training("a");
  d.add_held_out("c");
  Defaults(&d);
  Candidate tether = Make(d, {"tether.constant"}), slope = Make(d, {"ground.slope"});
  Candidate pair = Make(d, {"tether.constant", "ground.slope"});
  const Candidate fresh = pair;
  EXPECT_FALSE(StartAtBetter(tether, slope, &pair));  // neither fitted
  EXPECT_EQ(pair.mean0, fresh.mean0);
  tether.ok = slope.ok = true;
  tether.train = 2e-3;
  slope.train = 1e-3;  // the better one
  tether.values.assign(tether.genes.size(), 0.3);
  slope.values.assign(slope.genes.size(), 0.05);
  slope.values.back() = 99;  // the time offset far outside its range: clamped
  ASSERT_TRUE(StartAtBetter(tether, slope, &pair));
  EXPECT_DOUBLE_EQ(pair.sigma0, 0.1);
  for (size_t i = 0; i < pair.genes.size(); ++i) {
    const auto& g = pair.genes[i];
    if (pair.gene_effect[i] == "tether.constant") {
      EXPECT_EQ(pair.mean0[i], pair.nominal[i]) << g.name();  // absent, not the worse fit's
    } else if (pair.gene_effect[i] == "ground.slope") {
      EXPECT_EQ(pair.mean0[i], 0.05) << g.name();
    } else if (g.name() == "nuisance.time_offset_s") {
      EXPECT_EQ(pair.mean0[i], g.hi());
    }
  }
  EXPECT_EQ(pair.nominal, fresh.nominal);  // the range rule still judges the effect absent
}

// A screening fit on a fitted model (hold) keeps each shared gene within 2% of its value.
TEST(StartAt, AHeldStartShrinksTheSharedRangesToTwoPercent) {
  v1::DiagnosisSpec d;
  d.set_robot("caterpillar");
  d.add_training("a");
  d.add_held_out("c");
  Defaults(&d);
  Candidate base = Make(d, {}), tether = Make(d, {"tether.constant"});
  base.ok = true;
  base.values = {0.01};  // the time offset
  StartAt(base, &tether, true);
  const auto& g = tether.genes.back();
  EXPECT_NEAR(g.lo(), 0.0098, 1e-12);
  EXPECT_NEAR(g.hi(), 0.0102, 1e-12);
  EXPECT_EQ(tether.mean0.back(), 0.01);
  EXPECT_DOUBLE_EQ(tether.sigma0, 0.1);
  EXPECT_EQ(tether.genes[0].lo(), Make(d, {"tether.constant"}).genes[0].lo());  // not shared
}

}  // namespace
}  // namespace gaitforge::diagnosis
