// The on-policy family's loop (PPO, TRPO, TE-PPO, RL2, MAML): each iteration collects
// agent.rollout_rounds rounds of every env into a rollout buffer with the
// sampling policy (one batched forward pass per step, inference mode), cuts
// the episodes still running at the end of each round (they bootstrap from
// their last observation, as a time-limit truncation does), then runs one
// learner update on the whole buffer. The actor is told where episodes
// begin again (every env at a round's start, an env after its episode
// ends), so per-episode state such as TE-PPO's latent follows the episodes.
// Meta-learners trained on trials (RL2: learner->trials()) get one trial per
// env per iteration: the rounds keep each env's task variation, and the
// actor sees every step's outcome (Observe) to build its context. With a
// support/query split of the tasks (env.support_variations) a trial's rounds
// before learner->support_rounds() run support variations of one group, the
// rest its query variations.
// Checkpoint files: learner.pt (learner and torch generators).
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/agents/learner.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/loops/loops.h"
#include "manyworlds/experiments/run/checkpoint_io.h"
#include "manyworlds/rl/generator.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds::experiments {
namespace {

using Clock = std::chrono::steady_clock;

class OnPolicyAlgorithm : public Algorithm {
 public:
  OnPolicyAlgorithm(const AlgorithmSetup& s, std::unique_ptr<agents::OnPolicyLearner> learner,
                    int64_t rounds)
      : facts_(s.facts),
        seed_(s.config.experiment.seed),
        num_envs_(s.num_envs),
        round_length_(s.round_length),
        rounds_(rounds),
        learner_(std::move(learner)),
        buffer_(rounds * s.round_length, s.num_envs, s.facts.obs_dim, s.facts.action_dim) {

    env_task_ = torch::empty({num_envs_}, torch::kInt64);
    for (int64_t i = 0; i < num_envs_; ++i) env_task_[i] = i / s.config.env.envs_per_task;
    buffer_.task_index.copy_(env_task_);
    actions_.assign(num_envs_ * facts_.action_dim, 0.0f);
  }

  int64_t rounds_per_iteration() const override { return rounds_; }
  bool SupportsSplit() const override {
    return learner_->trials() && learner_->support_rounds() >= 1 &&
           learner_->support_rounds() < rounds_;
  }
  agents::Actor& actor() override { return learner_->AsActor(); }
  int64_t updates() const override { return learner_->num_updates(); }

  nlohmann::json TrainIteration(Collector& collector, int64_t first_round, int64_t) override {
    double t_act = 0.0, t_env = 0.0;
    EpisodeTotals totals;
    BatchedExecutor& exec = collector.executor();
    const int64_t d = facts_.obs_dim;
    agents::Actor& actor = learner_->AsActor();
    agents::ActorState state = actor.Initial(num_envs_);
    state.learning = true;
    const torch::Tensor all_envs = torch::ones({num_envs_}, torch::kBool);
    torch::Tensor ended_envs = torch::zeros({num_envs_}, torch::kBool);
    bool* ended_flags = ended_envs.data_ptr<bool>();
    const bool trials = learner_->trials();
    const bool observe = actor.WantsOutcomes();
    agents::StepOutcome outcome;
    for (int64_t k = 0; k < rounds_; ++k) {
      // trial mode: the iteration's rounds are one trial on one variation per env
      collector.BeginRound(seed_, first_round + k, trials ? rounds_ : 1,
                           learner_->support_rounds());
      if (k > 0) actor.Reset(all_envs, agents::ResetScope::kEpisode, state);
      for (int64_t s = 0; s < round_length_; ++s) {
        const int64_t t = k * round_length_ + s;
        const auto t0 = Clock::now();
        const auto obs = collector.observations();
        torch::Tensor obs_row = buffer_.obs[t];
        std::copy(obs.begin(), obs.end(), obs_row.data_ptr<float>());
        const auto steps = exec.episode_steps();
        float* ep = buffer_.episode_steps[t].data_ptr<float>();
        for (int64_t i = 0; i < num_envs_; ++i) ep[i] = static_cast<float>(steps[i]);
        {
          const agents::ActOutput out =
              actor.Act(obs_row, env_task_, state, agents::ActMode::kSample);
          buffer_.actions[t].copy_(out.action);
          buffer_.log_probs[t].copy_(out.log_prob);
          if (out.latent.defined()) {
            if (!buffer_.latents.defined()) {
              buffer_.latents = torch::zeros({buffer_.steps(), num_envs_, out.latent.size(1)});
            }
            buffer_.latents[t].copy_(out.latent);
          }
          const torch::Tensor action = out.action.contiguous();
          std::copy(action.data_ptr<float>(), action.data_ptr<float>() + action.numel(),
                    actions_.begin());
        }
        const auto t1 = Clock::now();
        collector.Step(actions_, totals);
        const auto rewards = exec.rewards();
        const auto terminated = exec.terminated();
        const auto truncated = exec.truncated();
        const auto final_obs = exec.final_env_obs();
        const auto next_obs = exec.env_obs();
        float* r = buffer_.rewards[t].data_ptr<float>();
        float* term = buffer_.terminated[t].data_ptr<float>();
        float* end = buffer_.ended[t].data_ptr<float>();
        float* fin = buffer_.final_obs[t].data_ptr<float>();
        const bool last = s + 1 == round_length_;
        bool any_ended = false;
        for (int64_t i = 0; i < num_envs_; ++i) {
          r[i] = rewards[i];
          term[i] = terminated[i] ? 1.0f : 0.0f;
          const bool ended = terminated[i] || truncated[i];
          ended_flags[i] = ended;
          any_ended = any_ended || ended;
          end[i] = ended || last ? 1.0f : 0.0f;
          // the round cuts a running episode: it ends at the current observation
          const float* src =
              ended ? final_obs.data() + i * d : (last ? next_obs.data() + i * d : nullptr);
          if (src != nullptr) {
            std::copy(src, src + d, fin + i * d);
          } else {
            std::fill(fin + i * d, fin + (i + 1) * d, 0.0f);
          }
        }
        if (observe) {
          // views of this step's buffer rows (actors copy what they keep)
          outcome.action = buffer_.actions[t];
          outcome.obs = buffer_.obs[t];
          outcome.reward = buffer_.rewards[t];
          outcome.ended = buffer_.ended[t];
          actor.Observe(outcome, state);
        }
        if (any_ended && !last) actor.Reset(ended_envs, agents::ResetScope::kEpisode, state);
        t_act += Seconds(t1 - t0);
        t_env += Seconds(Clock::now() - t1);
      }
      if (k + 1 == learner_->adapt_after_rounds()) actor.Adapt(all_envs, state);
    }
    const auto t2 = Clock::now();
    const agents::Metrics metrics = learner_->Update(buffer_);
    nlohmann::json row = {
        {"time_act_s", t_act},
        {"time_env_s", t_env},
        {"time_update_s", Seconds(Clock::now() - t2)},
        {"batch_size", buffer_.size()},
        {"train_success", totals.episodes > 0 && facts_.success_index >= 0
                              ? nlohmann::json(totals.success_sum / totals.episodes)
                              : nlohmann::json()},
    };
    totals.WriteTo(row, facts_.success_index >= 0);
    for (const auto& [name, value] : metrics.items()) row[name] = value;
    return row;
  }

  void Save(const std::filesystem::path& dir, nlohmann::json&) const override {
    WriteArchive(dir / "learner.pt", [&](torch::serialize::OutputArchive& archive) {
      learner_->Save(archive);
      archive.write("torch_generator", rl::GeneratorState(rl::DefaultGenerator()));
    });
  }

  void Load(const std::filesystem::path& dir, const nlohmann::json&) override {
    ReadArchive(dir / "learner.pt", [&](torch::serialize::InputArchive& archive) {
      learner_->Load(archive);
      torch::Tensor torch_state;
      archive.read("torch_generator", torch_state);
      rl::SetGeneratorState(rl::DefaultGenerator(), torch_state);
    });
  }

  void LoadPolicy(const std::filesystem::path& dir) override {
    ReadArchive(dir / "learner.pt",
                [&](torch::serialize::InputArchive& archive) { learner_->Load(archive); });
  }

 private:
  EnvFacts facts_;
  uint64_t seed_;
  int64_t num_envs_, round_length_, rounds_;
  std::unique_ptr<agents::OnPolicyLearner> learner_;
  rl::RolloutBuffer buffer_;
  torch::Tensor env_task_;
  std::vector<float> actions_;
};

}  // namespace

agents::PolicySpaces SetupSpaces(const AlgorithmSetup& s) {
  agents::PolicySpaces spaces;
  spaces.obs_dim = s.facts.obs_dim;
  spaces.action_dim = s.facts.action_dim;
  spaces.num_actions = s.facts.num_actions;
  spaces.num_tasks = s.num_tasks;
  return spaces;
}

std::unique_ptr<Algorithm> MakeOnPolicyAlgorithm(const AlgorithmSetup& setup,
                                                 std::unique_ptr<agents::OnPolicyLearner> learner,
                                                 int64_t rounds) {
  return std::make_unique<OnPolicyAlgorithm>(setup, std::move(learner), rounds);
}

}  // namespace manyworlds::experiments
