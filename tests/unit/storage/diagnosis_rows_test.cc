// Diagnoses' rows in the results database (storage/diagnosis_rows.h through StudyStore):
// stored, replaced as they progress, read with or without their files, listed in order.
#include <gtest/gtest.h>

#include "storage/study_store.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::storage {
namespace {

DiagnosisRecord Diagnosis(const std::string& id, int64_t created) {
  DiagnosisRecord r;
  r.diagnosis_id = id;
  r.name = "hose";
  r.spec = std::string("\x0a\x04hose\x00", 7);  // bytes, zero included
  r.state = "running";
  r.created_ms = r.updated_ms = created;
  return r;
}

TEST(DiagnosisRows, StoredReplacedAndReadBackWithTheirFiles) {
  testing::TempDir dir;
  auto store = OpenSqliteStore(dir.File("d.db"));
  ASSERT_TRUE(store.ok()) << store.status();
  ASSERT_TRUE((*store)->PutDiagnosis(Diagnosis("hose-2", 2000)).get().ok());
  ASSERT_TRUE((*store)->PutDiagnosis(Diagnosis("hose-1", 1000)).get().ok());
  DiagnosisRecord done = Diagnosis("hose-2", 2000);
  done.state = "completed";
  done.verdict = "found";
  done.report = R"({"verdict": "found"})";
  done.files = {{"diagnosis.json", "{}"}, {"diagnosis.svg", std::string("<svg>\0</svg>", 12)}};
  ASSERT_TRUE((*store)->PutDiagnosis(done).get().ok());

  auto got = (*store)->GetDiagnosis("hose-2", true);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->state, "completed");
  EXPECT_EQ(got->verdict, "found");
  EXPECT_EQ(got->report, done.report);
  EXPECT_EQ(got->spec, done.spec);
  ASSERT_EQ(got->files.size(), 2u);
  EXPECT_EQ(got->files[1].second, done.files[1].second);
  EXPECT_TRUE((*store)->GetDiagnosis("hose-2", false)->files.empty());

  // A later write without files keeps the stored ones.
  done.files.clear();
  done.error = "note";
  ASSERT_TRUE((*store)->PutDiagnosis(done).get().ok());
  EXPECT_EQ((*store)->GetDiagnosis("hose-2", true)->files.size(), 2u);

  auto all = (*store)->ListDiagnoses();
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 2u);
  EXPECT_EQ((*all)[0].diagnosis_id, "hose-1");  // oldest first
  EXPECT_TRUE((*all)[1].report.empty());        // listed without reports
  auto missing = (*store)->GetDiagnosis("nope", false);
  EXPECT_EQ(missing.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find("no diagnosis with id 'nope'"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::storage
