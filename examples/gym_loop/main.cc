// The classic Gym loop, in C++ with manyworlds:
//
//   env = gym.make("CartPole-v1")
//   obs, info = env.reset(seed=42)
//   for _ in range(1000):
//       action = env.action_space.sample()
//       obs, reward, terminated, truncated, info = env.step(action)
//       if terminated or truncated:
//           obs, info = env.reset()
#include <cstdio>
#include <vector>

#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"

int main() {
  std::unique_ptr<manyworlds::Env> env = manyworlds::Make("cartpole");
  env->Seed(42);      // dynamics and initial states
  env->SeedTask(0);   // which cart-pole (gravity, masses, ...) is sampled
  manyworlds::Observation obs = env->Reset();

  manyworlds::Rng action_rng(42);
  const manyworlds::Space& action_space = env->spec().action_space;
  double total_reward = 0.0;
  int episodes = 0;
  for (int t = 0; t < 1000; ++t) {
    const std::vector<float> action = action_space.Sample(action_rng);
    manyworlds::StepResult step = env->Step(action);
    total_reward += step.reward;
    obs = std::move(step.obs);
    if (step.terminated || step.truncated) {
      obs = env->Reset();
      ++episodes;
    }
  }
  std::printf("gym_loop: %s, 1000 steps, %d episodes ended, total reward %.1f\n",
              env->id().c_str(), episodes, total_reward);
  return 0;
}
