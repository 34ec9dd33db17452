#include "manyworlds/core/task_state.h"

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds {
namespace {

TEST(TaskStateTest, RoundTripsDoublesExactly) {
  Rng rng(11);
  std::vector<double> values;
  for (int i = 0; i < 200; ++i) values.push_back(rng.Normal() * 1e3);
  values.push_back(0.1);
  values.push_back(1.0 / 3.0);
  TaskState state{"cartpole", {{"mu", values}, {"index", 7}}};
  TaskState back = TaskState::Parse(state.Dump());
  EXPECT_EQ(back, state);
  EXPECT_EQ(back.params["mu"].get<std::vector<double>>(), values);
  EXPECT_EQ(TaskState::Parse(state.Dump(2)), state);
}

TEST(TaskStateTest, MalformedTextAndShapesAreRejected) {
  EXPECT_THROW(TaskState::Parse("{not json"), TaskStateError);
  EXPECT_THROW(TaskState::Parse("[1,2]"), TaskStateError);
  EXPECT_THROW(TaskState::Parse(R"({"env": 3, "params": {}})"), TaskStateError);
  EXPECT_THROW(TaskState::Parse(R"({"env": "x", "params": []})"), TaskStateError);
  EXPECT_THROW(TaskState::Parse(R"({"env": "x", "params": {}, "extra": 1})"), TaskStateError);
  EXPECT_NO_THROW(TaskState::Parse(R"({"env": "x", "params": {}})"));
}

TEST(TaskStateReaderTest, ValidatesFieldsAndNamesThem) {
  TaskState state{"bandit", {{"probs", {0.1, 0.9}}, {"n", 3}, {"bad", {0.5, "x"}}}};
  TaskStateReader reader(state, "bandit");
  EXPECT_EQ(reader.Floats("probs", 2, 0.0, 1.0), (std::vector<float>{0.1f, 0.9f}));
  EXPECT_EQ(reader.Integer("n", 0, 5), 3);
  EXPECT_THROW(reader.Floats("probs", 3, 0.0, 1.0), TaskStateError);
  EXPECT_THROW(reader.Floats("probs", 2, 0.0, 0.5), TaskStateError);
  EXPECT_THROW(reader.Numbers("bad", 2, 0.0, 1.0), TaskStateError);
  EXPECT_THROW(reader.Integer("n", 4, 5), TaskStateError);
  EXPECT_THROW(reader.Number("missing", 0, 1), TaskStateError);
  try {
    reader.ExpectKeys({"probs", "n"});
    FAIL();
  } catch (const TaskStateError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'bad'"), std::string::npos) << what;
    EXPECT_NE(what.find("'bandit'"), std::string::npos) << what;
  }
  EXPECT_THROW(TaskStateReader(state, "cartpole"), TaskStateError);
}

}  // namespace
}  // namespace manyworlds
