#pragma once
// What the coordinator's unit tests share: a calibration study's spec and a real SQLite
// store holding it.
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "gaitforge/v1/study.pb.h"
#include "storage/study_store.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::coordinator {

// A calibration of the piston force and link stiffness (and a time offset, a nuisance).
inline v1::StudySpec Calibration(const std::string& objective) {
  v1::StudySpec c;
  c.mutable_objective()->set_name(objective);
  for (const auto& [name, lo, hi] : std::vector<std::tuple<std::string, double, double>>{
           {"actuators.force_n", 7.0, 11.0},
           {"scale.link_stiffness", 0.7, 1.4},
           {"nuisance.time_offset_s", -0.05, 0.05}}) {
    auto* b = c.add_bounds();
    b->set_name(name);
    b->set_lo(lo);
    b->set_hi(hi);
  }
  return c;
}

// A store in dir holding study `id`, a caterpillar calibration in `state`.
inline std::unique_ptr<storage::StudyStore> StoreWithCalibration(testing::TempDir& dir,
                                                                const std::string& id,
                                                                const std::string& state) {
  auto store = storage::OpenSqliteStore(dir.File("s.db"));
  EXPECT_TRUE(store.ok()) << store.status();
  if (!store.ok()) return nullptr;
  storage::StudyRecord study;
  study.study_id = id;
  study.name = "cal";
  study.spec = Calibration("caterpillar.calibration").SerializeAsString();
  study.state = state;
  EXPECT_TRUE((*store)->CreateStudy(study).get().ok());
  return std::move(*store);
}

}  // namespace gaitforge::coordinator
