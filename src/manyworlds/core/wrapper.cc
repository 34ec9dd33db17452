#include "manyworlds/core/wrapper.h"

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

EnvSpec WrappedSpec(const std::unique_ptr<Env>& inner, std::string_view name) {
  if (!inner) throw Error("wrapper " + std::string(name) + " needs an env, got null");
  EnvSpec spec = inner->spec();
  spec.id += "|" + std::string(name);
  return spec;
}

}  // namespace

Wrapper::Wrapper(std::unique_ptr<Env> inner, std::string_view name)
    : Env(WrappedSpec(inner, name)), inner_(std::move(inner)) {
  inner_task_obs_.assign(inner_->spec().task_obs_space.flat_size(), 0.0f);
}

void Wrapper::Seed(uint64_t seed) {
  Env::Seed(seed);
  inner_->Seed(seed);
}

void Wrapper::SeedTask(uint64_t seed) {
  Env::SeedTask(seed);
  inner_->SeedTask(seed);
}

void Wrapper::SetMaxEpisodeSteps(int64_t max_episode_steps) {
  inner_->SetMaxEpisodeSteps(max_episode_steps);
  Env::SetMaxEpisodeSteps(max_episode_steps);
}

TaskState Wrapper::DoSampleTaskState(Rng&) { return inner_->SampleTaskState(); }

TaskState Wrapper::DoGetTaskState() const { return inner_->GetTaskState(); }

void Wrapper::DoSetTaskState(const TaskState& state) {
  inner_->SetTaskState(state);
  if (inner_->task_obs().size() == task_obs().size()) SetTaskObs(inner_->task_obs());
}

void Wrapper::DoReset(const ObsView& out) {
  inner_->Reset(ObsView{out.env_obs, inner_task_obs_, out.pixels});
  // The inner env may switch tasks in its Reset (SampleRandomTask does); keep
  // the mirrored task observation current. Wrappers with their own task
  // observation space are left alone.
  if (spec().task_obs_space == inner_->spec().task_obs_space) SetTaskObs(inner_task_obs_);
}

void Wrapper::DoStep(std::span<const float> action, const StepView& out) {
  inner_->Step(action, StepView{out.env_obs, inner_task_obs_, out.reward, out.terminated,
                                out.truncated, out.info, out.pixels});
}

}  // namespace manyworlds
