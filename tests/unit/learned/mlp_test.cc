// The learned-model component (workers/learned/mlp.h): an MLP learns a smooth map and
// predicts held-out rows, its training is the same for a seed, its file reads back to the
// same numbers, and bad files and data are refused with what was wrong.
#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "workers/learned/mlp.h"

namespace gaitforge::learned {
namespace {

struct Data {
  std::vector<std::vector<double>> x, y;
};

// y = (sin x0 + x1^2, x0 x1) on a grid over [-1.5, 1.5]^2.
Data Smooth() {
  Data d;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const double a = -1.5 + 3.0 * i / 19, b = -1.5 + 3.0 * j / 19;
      d.x.push_back({a, b});
      d.y.push_back({std::sin(a) + b * b, a * b});
    }
  return d;
}

TrainOptions Small() {
  TrainOptions o;
  o.hidden = {10};
  o.epochs = 3000;
  o.learning_rate = 0.02;
  return o;
}

TEST(MlpTest, LearnsASmoothMapAndPredictsHeldOutRows) {
  const Data d = Smooth();
  TrainReport r;
  auto m = Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), &r);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(r.train_n, 280);
  EXPECT_EQ(r.test_n, 120);
  EXPECT_GT(r.test_r, 0.99);
  EXPECT_LT(r.test_mse, 0.02);
  const std::vector<double> at = (*m)({0.5, -1.0});
  EXPECT_NEAR(at[0], std::sin(0.5) + 1.0, 0.1);
  EXPECT_NEAR(at[1], -0.5, 0.1);
}

TEST(MlpTest, TheSameSeedTrainsTheSameNetAndItsFileReadsBackExactly) {
  const Data d = Smooth();
  auto a = Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), nullptr);
  auto b = Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), nullptr);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->ToJson(), b->ToJson());
  auto back = Mlp::FromJson(a->ToJson(), "net.json");
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->inputs, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(back->activation, Activation::kLogSigmoid);
  for (const auto& x : d.x) EXPECT_EQ((*back)(x), (*a)(x));
  TrainOptions other = Small();
  other.seed = 2;
  EXPECT_NE(Train({"a", "b"}, {"u", "v"}, d.x, d.y, other, nullptr)->ToJson(), a->ToJson());
}

TEST(MlpTest, BadFilesAreRefusedNamingTheKey) {
  const Data d = Smooth();
  const std::string good = Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), nullptr)->ToJson();
  std::string wrong_format = good;
  wrong_format.replace(wrong_format.find("gaitforge.mlp.v1"), 16, "gaitforge.mlp.v9");
  EXPECT_NE(std::string(Mlp::FromJson(wrong_format, "net.json").status().message())
                .find("net.json: key 'format'"), std::string::npos);
  std::string short_mean = good;
  const size_t at = short_mean.find("\"input_mean\": [");
  short_mean.replace(at, short_mean.find(']', at) - at + 1, "\"input_mean\": [1]");
  EXPECT_NE(std::string(Mlp::FromJson(short_mean, "net.json").status().message())
                .find("key 'input_mean': expected a list of 2 numbers"), std::string::npos);
  std::string relu6 = good;
  relu6.replace(relu6.find("logsig"), 6, "relu6");
  EXPECT_NE(std::string(Mlp::FromJson(relu6, "net.json").status().message())
                .find("activation 'relu6' is not one of logsig, tanh, relu"), std::string::npos);
}

TEST(MlpTest, BadDataIsRefused) {
  Data d = Smooth();
  EXPECT_FALSE(Train({"a", "b"}, {"u", "v"}, {{1, 2}}, {{1, 2}}, Small(), nullptr).ok());
  d.y[3] = {1.0};
  EXPECT_NE(std::string(Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), nullptr).status().message())
                .find("row 3 has 2 inputs and 1 outputs, not 2 and 2"), std::string::npos);
  d.y[3] = {NAN, 1.0};
  EXPECT_FALSE(Train({"a", "b"}, {"u", "v"}, d.x, d.y, Small(), nullptr).ok());
  TrainOptions o = Small();
  o.test_fraction = 0.95;
  EXPECT_FALSE(Train({"a", "b"}, {"u", "v"}, Smooth().x, Smooth().y, o, nullptr).ok());
}

}  // namespace
}  // namespace gaitforge::learned
