#include "manyworlds/locomotion/locomotion.h"

#include <memory>

#include "manyworlds/locomotion/half_cheetah.h"

namespace manyworlds {

void RegisterLocomotionSuite(Registry& registry) {
  using locomotion::CheetahTask;
  using locomotion::HalfCheetahEnv;
  for (const CheetahTask task : {CheetahTask::kVelocity, CheetahTask::kDirection}) {
    const bool vel = task == CheetahTask::kVelocity;
    std::vector<OptionSpec> options = {
        {"horizon", OptionType::kInt, int64_t{vel ? 200 : 100},
         "episode length in steps (>= 1); episodes are truncated there"},
        {"hide_task", OptionType::kBool, true,
         "if true (meta-RL) the task observation is zero: infer the task from rewards"},
        {"throw_on_sim_warning", OptionType::kBool, false,
         "throw on a MuJoCo warning instead of ending the episode"}};
    registry.Add(EnvRegistration{
        vel ? "half-cheetah-vel" : "half-cheetah-dir", "locomotion",
        vel ? "Planar half-cheetah (MuJoCo); task = target forward velocity U[0, 2]"
            : "Planar half-cheetah (MuJoCo); task = run forward or backward",
        std::move(options), [task](const Options& o) -> std::unique_ptr<Env> {
          return std::make_unique<HalfCheetahEnv>(HalfCheetahEnv::Config{
              task, o.Int("horizon"), o.Bool("hide_task"), o.Bool("throw_on_sim_warning")});
        }});
  }
}

}  // namespace manyworlds
