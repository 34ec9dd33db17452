// CARE's task metadata: the shipped description embeddings load for MT10's
// tasks in order, and every malformed file is a one-line ConfigError.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/experiments/task_metadata.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;
using test_dirs::Scratch;
using test_dirs::SourceDir;

TaskSet Named(std::initializer_list<const char*> names) {
  TaskSet set;
  for (const char* name : names) set.tasks.push_back({name, "mt10", {}});
  return set;
}

std::string Message(const std::string& path, const TaskSet& tasks) {
  try {
    LoadTaskMetadata(path, tasks);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(TaskMetadataTest, TheShippedEmbeddingsLoadInTaskOrder) {
  const fs::path file = SourceDir() / "data/task_descriptions/metaworld_embeddings.json";
  const TaskSet tasks = Named({"reach", "push", "drawer-open", "drawer-close"});
  const torch::Tensor m = LoadTaskMetadata(file.string(), tasks);
  ASSERT_EQ(m.dim(), 2);
  EXPECT_EQ(m.size(0), 4);
  std::ifstream in(file);
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(m.size(1), doc["dim"].get<int64_t>());
  for (int64_t i = 0; i < 4; ++i) {
    const auto& v = doc["tasks"][tasks.tasks[i].name]["embedding"];
    EXPECT_FLOAT_EQ(m[i][0].item<float>(), v[0].get<float>());
    EXPECT_FLOAT_EQ(m[i][m.size(1) - 1].item<float>(), v.back().get<float>());
  }
  // Related tasks are closer than unrelated ones (the vectors are unit length).
  EXPECT_GT((m[2] * m[3]).sum().item<float>(), (m[0] * m[2]).sum().item<float>());
}

TEST(TaskMetadataTest, MalformedFilesAreOneLineErrors) {
  const fs::path dir = Scratch("task_metadata", "bad");
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    const fs::path p = dir / name;
    std::ofstream(p) << text;
    return p.string();
  };
  const TaskSet two = Named({"reach", "push"});
  const std::string reach = R"("reach": {"embedding": [1, 2]})";
  struct Case {
    std::string file, expect;
  } cases[] = {
      {(dir / "absent.json").string(), "cannot read it"},
      {write("text.json", "not json"), "not JSON"},
      {write("notasks.json", R"({"dim": 2})"), "needs a \"tasks\" object"},
      {write("missing.json", "{\"tasks\": {" + reach + "}}"), "no vector for task 'push'"},
      {write("ragged.json", "{\"tasks\": {" + reach + R"(, "push": {"embedding": [1]}}})"),
       "has 1 numbers, the first task 2"},
      {write("nan.json", "{\"tasks\": {" + reach + R"(, "push": [1, "x"]}})"),
       "not a finite number"},
      {write("empty.json", "{\"tasks\": {" + reach + R"(, "push": []}})"), "list of 1 to"},
  };
  for (const Case& c : cases) {
    const std::string msg = Message(c.file, two);
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.file << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find("agent.task_metadata"), std::string::npos) << msg;
  }
  // A bare list per task is accepted.
  const torch::Tensor ok = LoadTaskMetadata(
      write("bare.json", R"({"tasks": {"reach": [1, 2], "push": [3, 4]}})"), two);
  EXPECT_TRUE(torch::equal(ok, torch::tensor({{1.0f, 2.0f}, {3.0f, 4.0f}})));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds::experiments
