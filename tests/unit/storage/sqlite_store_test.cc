#include <gtest/gtest.h>
#include <sqlite3.h>

#include "storage/migrations.h"
#include "storage/study_store.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::storage {
namespace {

StudyRecord Study(const std::string& id) {
  StudyRecord r;
  r.study_id = id;
  r.name = "n";
  r.spec = std::string("\x01\x00\x02", 3);
  r.spec_json = "{}";
  r.state = "running";
  r.generations_total = 3;
  r.created_ms = r.updated_ms = 1000;
  return r;
}

IndividualRecord Ind(const std::string& id, int g, int m, double f) {
  IndividualRecord r;
  r.study_id = id;
  r.generation = g;
  r.member = m;
  r.genes = {0.1, 1.0 / 3.0, -0.0};
  r.valid = true;
  r.fitness = f;
  r.metrics = {{"loss", -f}};
  r.worker_id = "w";
  r.origin_generation = g;
  r.origin_member = m;
  return r;
}

int64_t Count(const std::string& path, const std::string& sql) {
  sqlite3* db;
  sqlite3_open(path.c_str(), &db);
  sqlite3_stmt* st;
  sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr);
  int64_t n = sqlite3_step(st) == SQLITE_ROW ? sqlite3_column_int64(st, 0) : -1;
  sqlite3_finalize(st);
  sqlite3_close(db);
  return n;
}

TEST(SqliteStore, WritesAreReadBackExactly) {
  testing::TempDir dir;
  auto store = OpenSqliteStore(dir.File("r.db"));
  ASSERT_TRUE(store.ok()) << store.status();
  auto& s = **store;
  ASSERT_TRUE(s.CreateStudy(Study("a")).get().ok());
  ASSERT_TRUE(s.AppendResults({Ind("a", 0, 0, 1.5), Ind("a", 0, 1, -2.25)}).get().ok());
  GenerationRecord g;
  g.study_id = "a";
  g.generation = 0;
  g.best = 1.5;
  g.mean = -0.375;
  g.evaluations = 2;
  g.engine_state = std::string("state\0bytes", 11);
  g.hall_of_fame = {HofRecord{0, 0, 0, {0.1, 1.0 / 3.0, -0.0}, true, 1.5}};
  g.study_state = "running";
  g.study_best = 1.5;
  g.study_evaluations = 2;
  g.committed_ms = 2000;
  ASSERT_TRUE(s.CommitGeneration(g).get().ok());

  auto study = s.GetStudy("a");
  ASSERT_TRUE(study.ok());
  EXPECT_EQ(study->generations_done, 1);
  EXPECT_EQ(study->spec, Study("a").spec);
  EXPECT_EQ(*study->best_fitness, 1.5);
  auto rows = s.Individuals("a", 0);
  ASSERT_TRUE(rows.ok());
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0].genes[1], 1.0 / 3.0);
  EXPECT_TRUE(std::signbit((*rows)[0].genes[2]));
  EXPECT_EQ((*rows)[1].fitness, -2.25);
  EXPECT_EQ((*rows)[1].metrics.at("loss"), 2.25);
  auto hof = s.HallOfFame("a", std::nullopt);
  ASSERT_TRUE(hof.ok());
  EXPECT_EQ(hof->first, 0);
  EXPECT_EQ(hof->second[0].genes[1], 1.0 / 3.0);
  auto state = s.LatestEngineState("a");
  ASSERT_TRUE(state.ok() && state->has_value());
  EXPECT_EQ((*state)->second, g.engine_state);
}

TEST(SqliteStore, AFailedWriteLeavesNothingAndOthersInTheBatchCommit) {
  testing::TempDir dir;
  auto store = OpenSqliteStore(dir.File("r.db"));
  ASSERT_TRUE(store.ok());
  auto& s = **store;
  ASSERT_TRUE(s.CreateStudy(Study("a")).get().ok());
  GenerationRecord g;
  g.study_id = "a";
  g.study_state = "running";
  g.carried = {Ind("a", 0, 5, 1.0)};
  auto first = s.CommitGeneration(g);
  auto dup = s.CommitGeneration(g);  // same generation again: primary key violation
  auto other = s.AppendResults({Ind("a", 0, 6, 2.0)});
  EXPECT_TRUE(first.get().ok());
  EXPECT_FALSE(dup.get().ok());
  EXPECT_TRUE(other.get().ok());
  EXPECT_EQ(Count(dir.File("r.db"), "SELECT COUNT(*) FROM generations"), 1);
  EXPECT_EQ(Count(dir.File("r.db"), "SELECT COUNT(*) FROM individuals"), 2);
}

TEST(SqliteStore, ReopeningAppliesNoMigrationTwiceAndKeepsData) {
  testing::TempDir dir;
  {
    auto store = OpenSqliteStore(dir.File("r.db"));
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE((*store)->CreateStudy(Study("a")).get().ok());
  }
  auto again = OpenSqliteStore(dir.File("r.db"), Durability{false});
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_TRUE((*again)->GetStudy("a").ok());
  EXPECT_EQ(Count(dir.File("r.db"), "SELECT COUNT(*) FROM schema_migrations"),
            static_cast<int64_t>(Migrations().size()));
  EXPECT_GE(Migrations().size(), 2u);
  EXPECT_EQ(Count(dir.File("r.db"), "SELECT COUNT(*) FROM pragma_journal_mode WHERE journal_mode='wal'"), 1);
}

TEST(SqliteStore, UnknownStudyAndGenerationAreClearErrors) {
  testing::TempDir dir;
  auto store = OpenSqliteStore(dir.File("r.db"));
  ASSERT_TRUE(store.ok());
  auto& s = **store;
  EXPECT_EQ(s.GetStudy("nope").status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(s.History("nope").status().code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(s.CreateStudy(Study("a")).get().ok());
  auto hof = s.HallOfFame("a", 4);
  EXPECT_EQ(hof.status().code(), absl::StatusCode::kOutOfRange);
  EXPECT_NE(hof.status().message().find("no generation yet"), std::string::npos);
  EXPECT_EQ(s.SetStudyState("nope", "cancelled", "").get().code(), absl::StatusCode::kNotFound);
}

TEST(SqliteStore, UnopenablePathIsAnError) {
  auto store = OpenSqliteStore("/nonexistent-dir/x/r.db");
  EXPECT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("/nonexistent-dir/x/r.db"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::storage
