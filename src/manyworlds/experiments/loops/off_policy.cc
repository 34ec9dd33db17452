// The off-policy family's loop (MTRL's multi-task SAC loop) around any
// OffPolicyLearner (SAC and its variants, Distral). Each step of a round:
//  1. actions: uniform random in (-1, 1) during the first warmup_steps steps,
//     then sampled from the learner (one batched forward pass, inference mode);
//  2. step the envs; store one transition per env with done = terminated (a
//     time-limit cut bootstraps) and next_obs = the episode's last
//     observation where it ended (with obs=pixels also both frames, the
//     learner acting on the frames);
//  3. after warm-up, gradient updates so that updates = floor((step -
//     warmup_steps) * updates_per_step), each on a replay batch.
// Checkpoint files: learner.pt (learner, replay and torch generators),
// replay.bin; state.json gets the warm-up action generator.
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/agents/deepmdp/deepmdp.h"
#include "manyworlds/agents/distral/distral.h"
#include "manyworlds/agents/hipbmdp/hipbmdp.h"
#include "manyworlds/agents/replay_buffer.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac_ae/sac_ae.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/loops/loops.h"
#include "manyworlds/experiments/metric_means.h"
#include "manyworlds/experiments/run/checkpoint_io.h"
#include "manyworlds/experiments/task_metadata.h"
#include "manyworlds/rl/generator.h"

namespace manyworlds::experiments {
namespace {

using Clock = std::chrono::steady_clock;

class OffPolicyAlgorithm : public Algorithm {
 public:
  OffPolicyAlgorithm(const AlgorithmSetup& s, const OffPolicyNetworkSize& size,
                     const OffPolicyLearnerFactory& make_learner)
      : config_(s.config),
        facts_(s.facts),
        num_envs_(s.num_envs),
        num_tasks_(s.num_tasks),
        round_length_(s.round_length) {
    const uint64_t seed = config_.experiment.seed;
    batch_size_ = config_.TotalBatchSize(num_tasks_);
    sampling_ = agents::ParseReplaySampling(config_.replay.sampling);
    if (sampling_ == agents::ReplaySampling::kBalanced && batch_size_ % num_tasks_ != 0) {
      throw ConfigError("balanced replay sampling needs the batch size (" +
                        std::to_string(batch_size_) +
                        ") to be a multiple of the number of tasks (" +
                        std::to_string(num_tasks_) + "); set experiment.batch_size");
    }
    if (config_.replay.capacity < num_tasks_) {
      throw ConfigError("'replay.capacity' (" + std::to_string(config_.replay.capacity) +
                        ") must be at least the number of tasks (" +
                        std::to_string(num_tasks_) + ")");
    }
    // one update holds, per batch row, the transition and every layer's activations and
    // gradients of the actor, two critics and their targets: refused before it is tried
    // (frames: a convolutional encoder's feature maps, about 16 floats per input byte, for
    // obs and next_obs, online and target)
    CheckMemoryEstimate(4.0 * static_cast<double>(batch_size_) *
                            (2.0 * static_cast<double>(facts_.obs_dim + facts_.action_dim) +
                             16.0 * static_cast<double>(size.hidden_dim) *
                                 (static_cast<double>(size.num_layers) + 1.0) +
                             64.0 * static_cast<double>(facts_.pixel_size())),
                        "an update of " + std::to_string(batch_size_) + " rows",
                        "agent.batch_size (rows per task; experiment.batch_size: in all) or "
                        "agent.hidden_dim");
    learner_ = make_learner(s);
    replay_ = std::make_unique<agents::ReplayBuffer>(config_.replay.capacity, facts_.obs_dim,
                                                     facts_.action_dim, num_tasks_,
                                                     facts_.pixel_size());
    replay_generator_ = rl::MakeGenerator(MixSeed(seed, kReplayStream));
    action_rng_.Seed(MixSeed(seed, kActionStream));
    env_task_ = torch::empty({num_envs_}, torch::kInt64);
    for (int64_t i = 0; i < num_envs_; ++i) env_task_[i] = i / config_.env.envs_per_task;
    obs_.assign(num_envs_ * facts_.obs_dim, 0.0f);
    pixels_.assign(num_envs_ * facts_.pixel_size(), 0);
    unit_.assign(num_envs_ * facts_.action_dim, 0.0f);
  }

  int64_t rounds_per_iteration() const override { return 1; }
  agents::Actor& actor() override { return learner_->AsActor(); }
  int64_t updates() const override { return updates_; }

  nlohmann::json TrainIteration(Collector& collector, int64_t round, int64_t step) override {
    const int64_t warmup = config_.experiment.warmup_steps;
    const double utd = config_.experiment.updates_per_step;
    double t_act = 0.0, t_env = 0.0, t_update = 0.0;
    EpisodeTotals totals;
    MetricMeans means;
    collector.BeginRound(config_.experiment.seed, round);
    BatchedExecutor& exec = collector.executor();
    const int64_t d = facts_.obs_dim, a = facts_.action_dim, p = facts_.pixel_size();
    for (int64_t s = 0; s < round_length_; ++s) {
      const auto t0 = Clock::now();
      ChooseActions(collector, step);
      const auto t1 = Clock::now();
      collector.Step(unit_, totals);
      const auto next = exec.env_obs();
      const auto final_obs = exec.final_env_obs();
      const auto next_pixels = exec.pixels();
      const auto final_pixels = exec.final_pixels();
      const auto rewards = exec.rewards();
      const auto terminated = exec.terminated();
      const auto truncated = exec.truncated();
      for (int64_t i = 0; i < num_envs_; ++i) {
        const bool ended = terminated[i] || truncated[i];
        const float* next_row = (ended ? final_obs.data() : next.data()) + i * d;
        const std::span<const float> obs(obs_.data() + i * d, static_cast<size_t>(d));
        const std::span<const float> action(unit_.data() + i * a, static_cast<size_t>(a));
        const std::span<const float> next_obs(next_row, static_cast<size_t>(d));
        if (p == 0) {
          replay_->Add(collector.env_tasks()[i], obs, action, rewards[i], next_obs,
                       terminated[i]);
          continue;
        }
        const uint8_t* next_frame = (ended ? final_pixels.data() : next_pixels.data()) + i * p;
        replay_->Add(collector.env_tasks()[i], obs, action, rewards[i], next_obs, terminated[i],
                     {pixels_.data() + i * p, static_cast<size_t>(p)},
                     {next_frame, static_cast<size_t>(p)});
      }
      const auto t2 = Clock::now();
      ++step;
      if (step > warmup) {
        const double exact = static_cast<double>(step - warmup) * utd;
        const double nearest = std::round(exact);
        const auto target = static_cast<int64_t>(
            std::abs(exact - nearest) < 1e-9 ? nearest : std::floor(exact));
        while (updates_ < target) {
          const agents::Batch& batch = replay_->Sample(batch_size_, sampling_, replay_generator_);
          means.Add(learner_->Update(batch));
          ++updates_;
        }
      }
      const auto t3 = Clock::now();
      t_act += Seconds(t1 - t0);
      t_env += Seconds(t2 - t1);
      t_update += Seconds(t3 - t2);
    }
    nlohmann::json row = {
        {"time_act_s", t_act},
        {"time_env_s", t_env},
        {"time_update_s", t_update},
        {"buffer_size", replay_->size()},
        {"train_success", totals.episodes > 0 && facts_.success_index >= 0
                              ? nlohmann::json(totals.success_sum / totals.episodes)
                              : nlohmann::json()},
    };
    totals.WriteTo(row, facts_.success_index >= 0);
    means.WriteTo(row);
    return row;
  }

  void Save(const std::filesystem::path& dir, nlohmann::json& state) const override {
    WriteArchive(dir / "learner.pt", [&](torch::serialize::OutputArchive& archive) {
      learner_->Save(archive);
      archive.write("replay_generator", rl::GeneratorState(replay_generator_));
      archive.write("torch_generator", rl::GeneratorState(rl::DefaultGenerator()));
    });
    replay_->SaveFile(dir / "replay.bin");
    nlohmann::json rng = nlohmann::json::array();
    for (uint64_t word : action_rng_.state()) rng.push_back(std::to_string(word));
    state["action_rng"] = rng;
  }

  void Load(const std::filesystem::path& dir, const nlohmann::json& state) override {
    Rng::State rng{};
    try {
      const auto& words = state.at("action_rng");
      if (!words.is_array() || words.size() != rng.size()) throw Error("action_rng");
      for (size_t i = 0; i < rng.size(); ++i) rng[i] = std::stoull(words[i].get<std::string>());
    } catch (const std::exception& e) {
      throw Error("checkpoint '" + dir.string() + "': malformed state.json (" + e.what() + ")");
    }
    ReadArchive(dir / "learner.pt", [&](torch::serialize::InputArchive& archive) {
      learner_->Load(archive);
      torch::Tensor replay_state, torch_state;
      archive.read("replay_generator", replay_state);
      archive.read("torch_generator", torch_state);
      rl::SetGeneratorState(replay_generator_, replay_state);
      rl::SetGeneratorState(rl::DefaultGenerator(), torch_state);
    });
    replay_->LoadFile(dir / "replay.bin");
    action_rng_.set_state(rng);
    updates_ = state.value("updates", int64_t{0});
  }

  void LoadPolicy(const std::filesystem::path& dir) override {
    ReadArchive(dir / "learner.pt",
                [&](torch::serialize::InputArchive& archive) { learner_->Load(archive); });
  }

 private:
  void ChooseActions(Collector& collector, int64_t step) {
    const auto current = collector.observations();
    std::copy(current.begin(), current.end(), obs_.begin());
    const auto frames = collector.executor().pixels();
    std::copy(frames.begin(), frames.end(), pixels_.begin());
    if (step < config_.experiment.warmup_steps) {
      for (float& a : unit_) a = static_cast<float>(action_rng_.Uniform(-1.0, 1.0));
      return;
    }
    const torch::Tensor a = learner_->AsActor()
                                .Act(collector.PolicyObservations(), env_task_, actor_state_,
                                     agents::ActMode::kSample)
                                .action.contiguous();
    std::copy(a.data_ptr<float>(), a.data_ptr<float>() + a.numel(), unit_.begin());
  }

  const TrainConfig& config_;
  EnvFacts facts_;
  int64_t num_envs_, num_tasks_, round_length_;
  int64_t batch_size_ = 0;
  agents::ReplaySampling sampling_ = agents::ReplaySampling::kBalanced;
  std::unique_ptr<agents::OffPolicyLearner> learner_;
  agents::ActorState actor_state_;  // unused by these memoryless actors
  std::unique_ptr<agents::ReplayBuffer> replay_;
  mutable at::Generator replay_generator_;
  Rng action_rng_;
  torch::Tensor env_task_;
  std::vector<float> obs_, unit_;
  std::vector<uint8_t> pixels_;  // the frames acted on, with obs=pixels
  int64_t updates_ = 0;
};

}  // namespace

std::unique_ptr<Algorithm> MakeOffPolicyAlgorithm(const AlgorithmSetup& setup,
                                                  const OffPolicyNetworkSize& size,
                                                  const OffPolicyLearnerFactory& make_learner) {
  return std::make_unique<OffPolicyAlgorithm>(setup, size, make_learner);
}

std::unique_ptr<Algorithm> MakeSacAlgorithm(const AlgorithmSetup& setup) {
  const agents::SacConfig agent = SeededAgentConfig<agents::SacConfig>(setup);
  return MakeOffPolicyAlgorithm(
      setup, {agent.hidden_dim, agent.num_layers}, [agent](const AlgorithmSetup& s) {
        const torch::Tensor task_metadata =
            agent.task_metadata.empty() ? torch::Tensor()
                                        : LoadTaskMetadata(agent.task_metadata, s.tasks);
        return std::make_unique<agents::SacLearner>(agent, s.facts.obs_dim, s.facts.action_dim,
                                                    s.num_tasks, task_metadata,
                                                    s.facts.pixel_shape);
      });
}

std::unique_ptr<Algorithm> MakeDistralAlgorithm(const AlgorithmSetup& setup) {
  const agents::DistralConfig agent = SeededAgentConfig<agents::DistralConfig>(setup);
  // Every task agent holds an actor and twin critics with targets; pi_0 is one more actor.
  return MakeOffPolicyAlgorithm(
      setup, {agent.hidden_dim, agent.num_layers}, [agent](const AlgorithmSetup& s) {
        return std::make_unique<agents::DistralLearner>(agent, s.facts.obs_dim,
                                                        s.facts.action_dim, s.num_tasks);
      });
}

namespace {

// The off-policy loop around a pixel learner Learner(config, obs_dim, action_dim, tasks, frames).
template <class Learner, class Config>
std::unique_ptr<Algorithm> MakeFramesAlgorithm(const AlgorithmSetup& setup) {
  const Config agent = SeededAgentConfig<Config>(setup);
  return MakeOffPolicyAlgorithm(
      setup, {agent.hidden_dim, agent.num_layers}, [agent](const AlgorithmSetup& s) {
        return std::make_unique<Learner>(agent, s.facts.obs_dim, s.facts.action_dim, s.num_tasks,
                                         s.facts.pixel_shape);
      });
}

}  // namespace

std::unique_ptr<Algorithm> MakeSacAeAlgorithm(const AlgorithmSetup& setup) {
  return MakeFramesAlgorithm<agents::SacAeLearner, agents::SacAeConfig>(setup);
}

std::unique_ptr<Algorithm> MakeDeepMdpAlgorithm(const AlgorithmSetup& setup) {
  return MakeFramesAlgorithm<agents::DeepMdpLearner, agents::DeepMdpConfig>(setup);
}

std::unique_ptr<Algorithm> MakeHipBmdpAlgorithm(const AlgorithmSetup& setup) {
  return MakeFramesAlgorithm<agents::HipBmdpLearner, agents::HipBmdpConfig>(setup);
}

}  // namespace manyworlds::experiments
