// A learner's checkpoint as bytes and back, for exact-resume tests.
#ifndef MANYWORLDS_TESTS_AGENTS_LEARNER_ARCHIVE_H_
#define MANYWORLDS_TESTS_AGENTS_LEARNER_ARCHIVE_H_

#include <sstream>
#include <string>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"

namespace manyworlds::agents {

inline std::string Archive(const Learner& learner) {
  torch::serialize::OutputArchive out;
  learner.Save(out);
  std::stringstream stream;
  out.save_to(stream);
  return stream.str();
}

inline void Restore(Learner& learner, const std::string& bytes) {
  std::stringstream stream(bytes);
  torch::serialize::InputArchive in;
  in.load_from(stream);
  learner.Load(in);
}

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_TESTS_AGENTS_LEARNER_ARCHIVE_H_
