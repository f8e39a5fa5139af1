// The coordinator with a real SQLite file and the real objectives, driven in-process.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <fstream>
#include <future>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "services/coordinator/coordinator.h"
#include "tests/integration/study_driver.h"
#include "workers/protocol/job_eval.h"
#include "workers/protocol/wire.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using coordinator::Coordinator;
using coordinator::CoordinatorOptions;

std::unique_ptr<Coordinator> Open(const std::string& db, core::Clock& clock,
                                  CoordinatorOptions o = {}) {
  auto store = storage::OpenSqliteStore(db);
  EXPECT_TRUE(store.ok()) << store.status();
  auto c = std::make_unique<Coordinator>(std::move(*store), o, clock);
  EXPECT_TRUE(c->RecoverStudies().ok());
  return c;
}

std::string Create(Coordinator& c, const v1::StudySpec& spec) {
  auto s = c.CreateStudy(spec);
  EXPECT_TRUE(s.ok()) << s.status();
  return s->study_id();
}

TEST(Coordinator, RunsAStudyToCompletionAndStoresEverything) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("r.db"), clock);
  const std::string id = Create(*c, SmallSpec(1));
  Drive(*c, {});
  auto s = c->GetStudy(id);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(s->state(), v1::STUDY_STATE_COMPLETED);
  EXPECT_EQ(s->generations_done(), 6);
  EXPECT_EQ(s->evaluations(), 30 + 5 * 20);  // elites are not evaluated again
  const StudyDump d = Dump(*c, id);
  EXPECT_EQ(d.generations, 6);
  EXPECT_EQ(d.fitness.size(), 180u);
  EXPECT_EQ(d.hof_fitness.size(), 60u);
  // The best never gets worse (the hall of fame is carried).
  for (int g = 1; g < 6; ++g) EXPECT_GE(d.hof_fitness[g * 10], d.hof_fitness[(g - 1) * 10]);
}

// Fair share (issue 30): the workers woken by a new generation each get an equal batch,
// not ever smaller ones (pending is divided among the active workers holding nothing).
TEST(Coordinator, IdleWorkersGetEqualShares) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("f.db"), clock);
  const std::string id = Create(*c, SmallSpec(3));  // 30 members in generation 0
  v1::HeartbeatRequest hb;
  for (const char* w : {"a", "b", "c"}) {
    hb.mutable_worker()->set_worker_id(w);
    ASSERT_TRUE(c->Heartbeat(hb).ok());
  }
  for (const char* w : {"a", "b", "c"}) {
    v1::LeaseRequest req;
    req.mutable_worker()->set_worker_id(w);
    req.set_max_jobs(100);
    auto lease = c->Lease(req);
    ASSERT_TRUE(lease.ok()) << lease.status();
    EXPECT_EQ(lease->jobs_size(), 10) << w;
  }
}

// A worker's part of a generation (issue 30): the first worker back from its batch finds
// few idle peers; it gets an even part of the generation less what it already had, not
// the idle workers' share of what is left, and past its part one job at a time.
TEST(Coordinator, AWorkerBackFirstTakesOnlyItsPartOfTheGeneration) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("p.db"), clock);
  Create(*c, SmallSpec(3));  // 30 members, 3 workers: a part is 10
  v1::HeartbeatRequest hb;
  for (const char* w : {"a", "b", "c"}) {
    hb.mutable_worker()->set_worker_id(w);
    ASSERT_TRUE(c->Heartbeat(hb).ok());
  }
  auto lease = [&](const char* w, int max_jobs) {
    v1::LeaseRequest req;
    req.mutable_worker()->set_worker_id(w);
    req.set_max_jobs(max_jobs);
    auto l = c->Lease(req);
    EXPECT_TRUE(l.ok()) << l.status();
    return l.ok() ? *l : v1::LeaseResponse();
  };
  auto report = [&](const char* w, const v1::LeaseResponse& l) {
    v1::ReportRequest r;
    r.mutable_worker()->set_worker_id(w);
    for (const auto& job : l.jobs()) {
      auto* res = r.add_results();
      *res->mutable_key() = job.key();
      res->set_lease_id(job.lease_id());
      res->mutable_evaluation()->set_valid(true);
      res->mutable_evaluation()->set_fitness(1.0);
    }
    ASSERT_TRUE(c->Report(r).ok());
  };
  const v1::LeaseResponse a1 = lease("a", 6), b1 = lease("b", 6), c1 = lease("c", 6);
  EXPECT_EQ(a1.jobs_size() + b1.jobs_size() + c1.jobs_size(), 18);
  report("a", a1);
  // 12 pending and a alone idle: the idle share would be 12; its part left is 4.
  const v1::LeaseResponse a2 = lease("a", 100);
  EXPECT_EQ(a2.jobs_size(), 4);
  report("a", a2);
  // Its part is taken: one job at a time, so a lost worker's jobs still get done.
  EXPECT_EQ(lease("a", 100).jobs_size(), 1);
  EXPECT_EQ(lease("b", 100).jobs_size(), 4);  // b has had 6 of its 10
}

// A study's robot descriptor goes to workers by content hash (issue 23): a leased job
// names it, GetRobot returns the text, after a restart too.
TEST(Coordinator, JobsNameTheRobotDescriptorByHash) {
  TempDir dir;
  core::ManualClock clock;
  std::ifstream in(GAITFORGE_SOURCE_DIR "/tests/fixtures/robots/twobox/robot.yaml");
  std::stringstream text;
  text << in.rdbuf();
  ASSERT_FALSE(text.str().empty());
  v1::StudySpec spec = SmallSpec(1, 12, 2);
  spec.mutable_objective()->set_name("robot.distance");
  spec.mutable_objective()->set_robot("twobox");
  spec.mutable_objective()->set_robot_descriptor(text.str());
  std::string hash;
  {
    auto c = Open(dir.File("h.db"), clock);
    Create(*c, spec);
    v1::LeaseRequest req;
    req.mutable_worker()->set_worker_id("w");
    req.set_max_jobs(2);
    auto lease = c->Lease(req);
    ASSERT_TRUE(lease.ok()) << lease.status();
    ASSERT_EQ(lease->jobs_size(), 2);
    // The objective goes once per lease, in the study's context, not in each job.
    ASSERT_EQ(lease->studies_size(), 1);
    EXPECT_FALSE(lease->jobs(0).has_objective());
    EXPECT_EQ(lease->jobs(0).bounds_size(), 0);
    const v1::ObjectiveSpec& o = lease->studies(0).objective();
    EXPECT_TRUE(o.robot_descriptor().empty());
    hash = o.robot_descriptor_hash();
    EXPECT_EQ(hash.size(), 64u);
    v1::GetRobotRequest get;
    get.set_hash(hash);
    auto got = c->GetRobot(get);
    ASSERT_TRUE(got.ok()) << got.status();
    EXPECT_EQ(got->text(), text.str());
    get.set_hash("0123");
    EXPECT_EQ(c->GetRobot(get).status().code(), absl::StatusCode::kNotFound);
    get.clear_hash();
    EXPECT_EQ(c->GetRobot(get).status().code(), absl::StatusCode::kInvalidArgument);
  }
  // A restarted coordinator that has leased nothing yet still knows it.
  auto c = Open(dir.File("h.db"), clock);
  v1::GetRobotRequest get;
  get.set_hash(hash);
  auto got = c->GetRobot(get);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->text(), text.str());
}

v1::LeaseRequest WaitingLease(const char* worker, int wait_ms) {
  v1::LeaseRequest req;
  req.mutable_worker()->set_worker_id(worker);
  req.set_max_jobs(100);
  req.set_wait_ms(wait_ms);
  return req;
}

// Starts a long poll of up to 10 s; its answer arrives on the future.
std::future<absl::StatusOr<v1::LeaseResponse>> StartLongPoll(
    Coordinator& c, const char* worker, std::shared_ptr<std::atomic<bool>> cancelled = nullptr) {
  auto answer = std::make_shared<std::promise<absl::StatusOr<v1::LeaseResponse>>>();
  auto f = answer->get_future();
  c.LeaseAsync(WaitingLease(worker, 10000), [answer](auto r) { answer->set_value(std::move(r)); },
               std::move(cancelled));
  return f;
}

// A long poll holds no thread: the dispatcher answers it when jobs arrive (issue 30).
TEST(Coordinator, AWaitingLeaseIsAnsweredWhenJobsArrive) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("w.db"), clock);
  auto f = StartLongPoll(*c, "w");
  EXPECT_EQ(f.wait_for(std::chrono::seconds(0)), std::future_status::timeout);  // no jobs yet
  Create(*c, SmallSpec(4));
  ASSERT_EQ(f.wait_for(std::chrono::seconds(9)), std::future_status::ready);
  auto lease = f.get();
  ASSERT_TRUE(lease.ok()) << lease.status();
  ASSERT_EQ(lease->jobs_size(), 30);
  for (const auto& j : lease->jobs()) EXPECT_EQ(j.key().generation(), 0);
}

// A caller that went away (its call cancelled) is leased nothing, even when jobs arrive.
TEST(Coordinator, ACancelledWaitingLeaseIsLeasedNothing) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("x.db"), clock);
  auto cancelled = std::make_shared<std::atomic<bool>>(false);
  auto f = StartLongPoll(*c, "gone", cancelled);
  cancelled->store(true);
  Create(*c, SmallSpec(5));
  EXPECT_EQ(f.get().status().code(), absl::StatusCode::kCancelled);
  EXPECT_EQ(c->QueueStats().leased, 0);  // every job is still there for others
}

TEST(Coordinator, ShutdownAnswersWaitingLeases) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("s.db"), clock);
  auto f = StartLongPoll(*c, "w");
  c->Shutdown();
  ASSERT_EQ(f.wait_for(std::chrono::seconds(9)), std::future_status::ready);
  auto lease = f.get();
  ASSERT_TRUE(lease.ok()) << lease.status();
  EXPECT_EQ(lease->jobs_size(), 0);
}

TEST(Coordinator, ResultDoesNotDependOnBatchingOrReportOrder) {
  TempDir dir;
  core::ManualClock clock;
  auto a = Open(dir.File("a.db"), clock);
  auto b = Open(dir.File("b.db"), clock);
  const std::string ia = Create(*a, SmallSpec(9));
  const std::string ib = Create(*b, SmallSpec(9));
  Drive(*a, {.batch = 1});
  Drive(*b, {.batch = 7, .reverse = true});
  EXPECT_EQ(Dump(*a, ia), Dump(*b, ib));
}

TEST(Coordinator, ARestartedCoordinatorResumesAndEndsBitIdentical) {
  TempDir dir;
  core::ManualClock clock;
  auto ref = Open(dir.File("ref.db"), clock);
  const std::string rid = Create(*ref, SmallSpec(4));
  Drive(*ref, {.batch = 5});

  std::string id;
  {
    auto c = Open(dir.File("r.db"), clock);
    id = Create(*c, SmallSpec(4));
    Drive(*c, {.batch = 5, .max_reports = 9});  // mid-generation 1
    c->Shutdown();
  }
  for (int restart = 0; restart < 3; ++restart) {
    auto c = Open(dir.File("r.db"), clock);
    auto s = c->GetStudy(id);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->state(), v1::STUDY_STATE_RUNNING);
    Drive(*c, {.batch = 3, .max_reports = 7});
  }
  auto c = Open(dir.File("r.db"), clock);
  Drive(*c, {.batch = 11});
  EXPECT_EQ(c->GetStudy(id)->state(), v1::STUDY_STATE_COMPLETED);
  EXPECT_EQ(Dump(*c, id), Dump(*ref, rid));
  // Results stored before a restart were not evaluated again.
  EXPECT_EQ(c->GetStudy(id)->evaluations(), ref->GetStudy(rid)->evaluations());
}

// A report whose call failed while the coordinator restarted is sent again; when its
// results had been stored before the restart it is acknowledged as duplicates, not refused
// (the restarted process's queue does not hold jobs that are already done).
TEST(Coordinator, AReportSentAgainAfterARestartIsADuplicate) {
  TempDir dir;
  core::ManualClock clock;
  v1::ReportRequest rep;
  {
    auto c = Open(dir.File("d.db"), clock);
    Create(*c, SmallSpec(4));
    v1::LeaseRequest lreq;
    lreq.mutable_worker()->set_worker_id("w");
    lreq.set_max_jobs(2);
    auto lease = c->Lease(lreq);
    ASSERT_TRUE(lease.ok()) << lease.status();
    ASSERT_TRUE(worker::ExpandLease(*lease).ok());
    ASSERT_EQ(lease->jobs_size(), 2);
    rep = worker::StartReport(lreq.worker(), *lease);
    for (int i = 0; i < 2; ++i)
      worker::FillResult(rep.mutable_results(i),
                         worker::EvaluateJob(objectives::DefaultRegistry(), lease->jobs(i), {}), 0);
    auto first = c->Report(rep);
    ASSERT_TRUE(first.ok()) << first.status();
    EXPECT_EQ(first->accepted(), 2);
    c->Shutdown();
  }
  auto c = Open(dir.File("d.db"), clock);
  auto again = c->Report(rep);
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(again->accepted(), 0);
  EXPECT_EQ(again->duplicates(), 2);
}

TEST(Coordinator, CancelThenResumeContinuesIdentically) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("r.db"), clock);
  const std::string ref = Create(*c, SmallSpec(5));
  Drive(*c, {});
  const std::string id = Create(*c, SmallSpec(5));
  Drive(*c, {.batch = 4, .max_reports = 10});
  auto cancelled = c->CancelStudy(id);
  ASSERT_TRUE(cancelled.ok()) << cancelled.status();
  EXPECT_EQ(cancelled->state(), v1::STUDY_STATE_CANCELLED);
  EXPECT_EQ(Drive(*c, {}), 0) << "a cancelled study hands out no work";
  EXPECT_EQ(c->CancelStudy(id).status().code(), absl::StatusCode::kFailedPrecondition);
  auto resumed = c->ResumeStudy(id);
  ASSERT_TRUE(resumed.ok()) << resumed.status();
  Drive(*c, {.batch = 9});
  EXPECT_EQ(c->GetStudy(id)->state(), v1::STUDY_STATE_COMPLETED);
  EXPECT_EQ(Dump(*c, id), Dump(*c, ref));
  EXPECT_EQ(c->ResumeStudy(id).status().code(), absl::StatusCode::kFailedPrecondition);
}

TEST(Coordinator, BadReportsAreRefusedAndChangeNothing) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("r.db"), clock);
  const std::string id = Create(*c, SmallSpec(2));
  v1::LeaseRequest lreq;
  lreq.mutable_worker()->set_worker_id("w1");
  lreq.set_max_jobs(2);
  auto lease = c->Lease(lreq);
  ASSERT_TRUE(lease.ok());
  ASSERT_EQ(lease->jobs_size(), 2);

  auto report = [&](const std::string& worker, const v1::Job& job, double fitness, bool valid,
                    uint64_t lease_id) {
    v1::ReportRequest r;
    r.mutable_worker()->set_worker_id(worker);
    auto* res = r.add_results();
    *res->mutable_key() = job.key();
    res->set_lease_id(lease_id);
    res->mutable_evaluation()->set_valid(valid);
    res->mutable_evaluation()->set_fitness(fitness);
    return c->Report(r);
  };
  const auto& job = lease->jobs(0);
  // A job the worker does not hold.
  auto s = report("w2", job, 1.0, true, 0);
  EXPECT_EQ(s.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(s.status().message().find("does not hold this job"), std::string::npos);
  // A non-finite fitness.
  s = report("w1", job, INFINITY, true, job.lease_id());
  EXPECT_EQ(s.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.status().message().find("evaluation.fitness"), std::string::npos);
  // An unknown study and a job from the future.
  v1::Job bogus = job;
  bogus.mutable_key()->set_study_id("nope");
  EXPECT_EQ(report("w1", bogus, 1, true, job.lease_id()).status().code(),
            absl::StatusCode::kFailedPrecondition);
  bogus = job;
  bogus.mutable_key()->set_generation(3);
  EXPECT_EQ(report("w1", bogus, 1, true, job.lease_id()).status().code(),
            absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(c->GetStudy(id)->evaluations(), 0);
  // The real result is accepted once; a repeat is a counted duplicate.
  auto ok = report("w1", job, -3.0, true, job.lease_id());
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->accepted(), 1);
  auto dup = report("w1", job, -3.0, true, job.lease_id());
  ASSERT_TRUE(dup.ok());
  EXPECT_EQ(dup->duplicates(), 1);
  EXPECT_EQ(c->GetStudy(id)->evaluations(), 1);
  EXPECT_EQ(c->QueueStats().duplicates, 1);
  // Malformed lease requests.
  lreq.set_max_jobs(0);
  EXPECT_EQ(c->Lease(lreq).status().code(), absl::StatusCode::kInvalidArgument);
  lreq.set_max_jobs(1);
  lreq.mutable_worker()->clear_worker_id();
  EXPECT_EQ(c->Lease(lreq).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(Coordinator, AWorkerOfAnotherSimulatorBuildIsRefused) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("r.db"), clock);
  const std::string id = Create(*c, SmallSpec(2));
  v1::LeaseRequest lreq;
  lreq.mutable_worker()->set_worker_id("a");
  lreq.mutable_worker()->set_sim_build("build-A");
  lreq.set_max_jobs(1);
  auto first = c->Lease(lreq);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->jobs_size(), 1);
  EXPECT_EQ(c->GetStudy(id)->sim_build(), "build-A");
  // Another build gets no job of this study, with a reason.
  lreq.mutable_worker()->set_worker_id("b");
  lreq.mutable_worker()->set_sim_build("build-B");
  auto other = c->Lease(lreq);
  EXPECT_EQ(other.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(other.status().message().find("simulator build 'build-B'"), std::string::npos)
      << other.status();
  // Nor may it report for it, even with a real lease id.
  v1::ReportRequest rep;
  rep.mutable_worker()->set_worker_id("a");
  rep.mutable_worker()->set_sim_build("build-B");
  auto* res = rep.add_results();
  *res->mutable_key() = first->jobs(0).key();
  res->set_lease_id(first->jobs(0).lease_id());
  res->mutable_evaluation()->set_valid(true);
  EXPECT_EQ(c->Report(rep).status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(c->GetStudy(id)->evaluations(), 0);
  // The pin survives a restart.
  c.reset();
  auto again = Open(dir.File("r.db"), clock);
  EXPECT_EQ(again->GetStudy(id)->sim_build(), "build-A");
}

// `spec` run again in "b.db" in batches of 3 reported in reverse, the coordinator restarted
// after 40 reports, then in batches of 5: the study ends as `expected`.
void ExpectSameInSmallReversedBatchesAfterARestart(const v1::StudySpec& spec, TempDir& dir,
                                                   core::ManualClock& clock,
                                                   const StudyDump& expected) {
  std::string ib;
  {
    auto b = Open(dir.File("b.db"), clock);
    ib = Create(*b, spec);
    Drive(*b, {.batch = 3, .reverse = true, .max_reports = 40});
  }
  auto b = Open(dir.File("b.db"), clock);  // restarted mid-study
  Drive(*b, {.batch = 5});
  EXPECT_EQ(expected, Dump(*b, ib));
}

TEST(Coordinator, CmaesStudyConvergesAndIsIndependentOfBatchingAndRestarts) {
  TempDir dir;
  core::ManualClock clock;
  auto spec = SmallSpec(3, 0, 400);
  spec.set_engine("cmaes");
  spec.mutable_objective()->set_name("analytic.sphere");
  spec.mutable_cmaes()->set_max_evaluations(6000);
  spec.mutable_cmaes()->set_stop_fitness(-1e-10);
  auto a = Open(dir.File("a.db"), clock);
  const std::string ia = Create(*a, spec);
  Drive(*a, {.batch = 64});
  auto sa = a->GetStudy(ia);
  EXPECT_EQ(sa->state(), v1::STUDY_STATE_COMPLETED);
  EXPECT_GT(sa->best_fitness(), -1e-8) << "CMA-ES solves the 13-d sphere";
  EXPECT_LT(sa->evaluations(), 6000);
  ExpectSameInSmallReversedBatchesAfterARestart(spec, dir, clock, Dump(*a, ia));
}

// Log genes through the coordinator: the engine searches ln(x), the store and the hall of
// fame hold x, and the result is the same across batching, report order and a restart.
TEST(Coordinator, LogGenesAreStoredInUnitsAndResumeBitIdentically) {
  TempDir dir;
  core::ManualClock clock;
  auto spec = SmallSpec(4, 0, 400);
  spec.set_engine("cmaes");
  spec.mutable_objective()->set_name("analytic.sphere");
  for (int i = 0; i < 3; ++i) {
    auto* b = spec.add_bounds();
    b->set_name(absl::StrCat("x", i));
    b->set_lo(0.01);
    b->set_hi(1.0);
    b->set_log(true);
  }
  spec.mutable_cmaes()->set_max_evaluations(3000);
  spec.mutable_cmaes()->set_stop_fitness(-1e-10);
  auto a = Open(dir.File("a.db"), clock);
  const std::string ia = Create(*a, spec);
  Drive(*a, {.batch = 64});
  EXPECT_GT(a->GetStudy(ia)->best_fitness(), -1e-8) << "CMA-ES solves the sphere in ln(x)";
  auto hof = a->HallOfFame(ia, std::nullopt);
  ASSERT_TRUE(hof.ok()) << hof.status();
  // The sphere's optimum sits at 0.6, 0.4, 0.6 of each range in units (analytic.cc).
  const std::vector<double> genes(hof->entries(0).individual().genes().begin(),
                                  hof->entries(0).individual().genes().end());
  EXPECT_NEAR(genes.at(0), 0.01 + 0.6 * 0.99, 1e-4);
  EXPECT_NEAR(genes.at(1), 0.01 + 0.4 * 0.99, 1e-4);
  auto first = a->Individuals(ia, 0);
  ASSERT_TRUE(first.ok());
  for (const auto& ind : first->individuals())
    for (double g : ind.genes()) {
      EXPECT_GE(g, 0.01);
      EXPECT_LE(g, 1.0);
    }
  ExpectSameInSmallReversedBatchesAfterARestart(spec, dir, clock, Dump(*a, ia));
}

TEST(Coordinator, SweepStudyRefinesTheGridWithNelderMead) {
  TempDir dir;
  core::ManualClock clock;
  auto spec = SmallSpec(1, 0, 500);
  spec.set_engine("sweep");
  spec.mutable_objective()->set_name("analytic.rosenbrock");
  (*spec.mutable_objective()->mutable_params())["shift"] = 0.0;
  for (const char* n : {"x", "y"}) {
    auto* b = spec.add_bounds();
    b->set_name(n);
    b->set_lo(-1.0);
    b->set_hi(1.5);
  }
  spec.mutable_sweep()->add_points_per_axis(9);
  auto c = Open(dir.File("r.db"), clock);
  const std::string id = Create(*c, spec);
  Drive(*c, {.batch = 10});
  auto s = c->GetStudy(id);
  EXPECT_EQ(s->state(), v1::STUDY_STATE_COMPLETED);
  auto grid = c->Individuals(id, 0);
  ASSERT_TRUE(grid.ok());
  EXPECT_EQ(grid->individuals_size(), 81);
  double grid_best = -1e300;
  for (const auto& i : grid->individuals()) grid_best = std::max(grid_best, i.evaluation().fitness());
  EXPECT_GT(s->best_fitness(), grid_best);
  EXPECT_GT(s->best_fitness(), -1e-6) << "Nelder-Mead reaches Rosenbrock's optimum";
}

TEST(Coordinator, InfeasibleMembersRankBelowFeasibleOnesAndAreKept) {
  TempDir dir;
  core::ManualClock clock;
  auto spec = SmallSpec(8, 40, 8);
  spec.mutable_objective()->set_name("analytic.sphere");
  auto* k = spec.add_constraints();
  k->set_metric("loss");
  k->set_min(80.0);  // feasible only away from the optimum: loss >= 80
  auto c = Open(dir.File("r.db"), clock);
  const std::string id = Create(*c, spec);
  Drive(*c, {});
  int infeasible = 0;
  for (int g = 0; g < 8; ++g) {
    auto inds = c->Individuals(id, g);
    ASSERT_TRUE(inds.ok());
    EXPECT_EQ(inds->individuals_size(), 40) << "nothing is dropped";
    for (const auto& i : inds->individuals()) {
      const double loss = -i.evaluation().fitness();
      EXPECT_DOUBLE_EQ(i.violation(), loss < 80.0 ? 80.0 - loss : 0.0);
      infeasible += i.violation() > 0;
    }
    auto hof = c->HallOfFame(id, g);
    ASSERT_TRUE(hof.ok());
    EXPECT_LE(hof->entries(0).individual().evaluation().fitness(), -80.0)
        << "the best is the best feasible member";
  }
  EXPECT_GT(infeasible, 0);
}

TEST(Coordinator, InvalidSpecsAreRefusedAndNothingIsStored) {
  TempDir dir;
  core::ManualClock clock;
  auto c = Open(dir.File("r.db"), clock);
  auto spec = SmallSpec(1);
  spec.set_population(1);
  auto s = c->CreateStudy(spec);
  EXPECT_EQ(s.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.status().message().find("field 'population' = 1 is out of range [2, 100000]"),
            std::string::npos)
      << s.status();
  spec = SmallSpec(1);
  spec.mutable_objective()->set_name("analytic.none");
  EXPECT_EQ(c->CreateStudy(spec).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(c->ListStudies()->empty());
  EXPECT_EQ(c->GetStudy("nope").status().code(), absl::StatusCode::kNotFound);
}

TEST(Coordinator, ALostJobIsRetriedThenPoisonedSoTheGenerationFinishes) {
  TempDir dir;
  core::ManualClock clock;
  CoordinatorOptions o;
  o.lease_ms = 1000;
  o.max_attempts = 2;
  o.backup_after_ms = 0;
  auto c = Open(dir.File("r.db"), clock, o);
  const std::string id = Create(*c, SmallSpec(3, 12, 2));
  v1::LeaseRequest lreq;
  lreq.mutable_worker()->set_worker_id("dies");
  lreq.set_max_jobs(1);
  for (int attempt = 0; attempt < 2; ++attempt) {
    auto l = c->Lease(lreq);
    ASSERT_TRUE(l.ok());
    ASSERT_EQ(l->jobs_size(), 1);
    EXPECT_EQ(l->jobs(0).key().member(), 0);
    clock.Advance(1001);
    c->Tick();
  }
  Drive(*c, {});
  auto inds = c->Individuals(id, 0);
  ASSERT_TRUE(inds.ok());
  EXPECT_FALSE(inds->individuals(0).evaluation().valid());
  EXPECT_NE(inds->individuals(0).evaluation().reason().find("poisoned"), std::string::npos);
  EXPECT_EQ(c->GetStudy(id)->state(), v1::STUDY_STATE_COMPLETED);
  EXPECT_EQ(c->QueueStats().poisoned, 1);
}

}  // namespace
}  // namespace gaitforge::testing
