// CARE's task metadata: one fixed vector per task (e.g. an embedded
// description), read from a JSON file whose "tasks" object maps task names
// to {"embedding": [numbers]} (the format scripts/embed_task_descriptions.py
// writes, data/task_descriptions/metaworld_embeddings.json).
#ifndef MANYWORLDS_EXPERIMENTS_TASK_METADATA_H_
#define MANYWORLDS_EXPERIMENTS_TASK_METADATA_H_

#include <string>

#include <torch/torch.h>

#include "manyworlds/experiments/task_set.h"

namespace manyworlds::experiments {

// (tasks.size(), D) float32, row i the vector of tasks.tasks[i].name.
// ConfigError (one line) on a missing or unreadable file, malformed JSON, a
// task without a vector, vectors of different lengths or non-finite values.
torch::Tensor LoadTaskMetadata(const std::string& path, const TaskSet& tasks);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_TASK_METADATA_H_
