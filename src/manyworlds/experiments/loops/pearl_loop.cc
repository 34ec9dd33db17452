// PEARL's loop (oyster's rl_algorithm.py schedule, on envs stepped in
// lockstep).
//
// PEARL's training tasks are the run's (task, variation) pairs (with a
// support/query split, its (task, group) pairs): key offset(task) +
// variation (or group), each with its own RL replay partition and
// encoder-buffer partition (replay.capacity rows split evenly between the
// keys, for each of the two buffers). One iteration is one trial of
// agent.episodes_per_iteration() rounds, every env on one variation
// (the collector's trial mode):
//  1. the encoder partitions of the iteration's keys are cleared (the
//     encoder trains on recent data, as oyster), unless still warming up;
//  2. prior_episodes rounds with z drawn from the prior N(0, I) per env and
//     round, stored in both buffers; posterior_episodes rounds with z drawn
//     from the posterior of embedding_batch_size transitions sampled from
//     the key's encoder partition (re-inferred every round, oyster's
//     update_posterior_rate 1), stored in both; extra_posterior_episodes
//     such rounds stored in the RL buffer only;
//  3. updates_per_iteration gradient steps, each on meta_batch keys drawn
//     uniformly with replacement among the keys that hold data, with
//     embedding_batch_size context and batch_size RL transitions per key.
// Iterations that start before experiment.warmup_steps (env steps per env)
// only collect, every round with z from the prior (oyster's
// num_initial_steps), and keep their encoder data.
//
// With a split, the prior_episodes rounds run support variations of the
// env's group and only they fill the encoder's buffer; the later rounds run
// query variations with z inferred from that support context.
//
// Differences from oyster: every env collects every iteration (oyster
// collects for num_tasks_sample random tasks); the first round of the
// extra-posterior phase uses the posterior too (oyster's begins with a
// prior z); counts are episodes per env, not steps per task.
//
// Metrics add train_return_prior and train_return_posterior (episodes with
// z from the prior and from the posterior): their gap is the adaptation the
// encoder gives on training tasks. Checkpoint files: learner.pt (learner and
// generators), replay.bin, encoder_replay.bin.
#include <algorithm>
#include <chrono>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "manyworlds/agents/pearl/pearl.h"
#include "manyworlds/agents/replay_buffer.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/loops/loops.h"
#include "manyworlds/experiments/metric_means.h"
#include "manyworlds/experiments/run/checkpoint_io.h"
#include "manyworlds/rl/generator.h"

namespace manyworlds::experiments {
namespace {

using Clock = std::chrono::steady_clock;

enum class Phase { kPrior, kPosterior, kExtraPosterior };

class PearlAlgorithm : public Algorithm {
 public:
  explicit PearlAlgorithm(const AlgorithmSetup& s)
      : config_(s.config), facts_(s.facts), num_envs_(s.num_envs), round_length_(s.round_length) {
    const TrainConfig defaults;
    if (config_.replay.sampling != defaults.replay.sampling) {
      throw ConfigError("'replay.sampling' does not apply to pearl (it samples per task)");
    }
    if (config_.experiment.updates_per_step != defaults.experiment.updates_per_step ||
        config_.experiment.batch_size != defaults.experiment.batch_size) {
      throw ConfigError(
          "'experiment.updates_per_step' and 'experiment.batch_size' do not apply to pearl; "
          "set agent.updates_per_iteration, agent.meta_batch and agent.batch_size");
    }
    const agents::PearlConfig agent = SeededAgentConfig<agents::PearlConfig>(s);
    learner_ = std::make_unique<agents::PearlLearner>(agent, facts_.obs_dim, facts_.action_dim);
    split_ = s.tasks.has_split();
    group_size_ = split_ ? s.tasks.support_variations + s.tasks.query_variations : 1;
    for (int64_t t = 0; t < s.tasks.size(); ++t) {
      key_offset_.push_back(num_keys_);
      num_keys_ += split_ ? s.tasks.Groups(t)
                          : static_cast<int64_t>(s.tasks.tasks[t].variations.size());
    }
    if (config_.replay.capacity < num_keys_) {
      throw ConfigError("'replay.capacity' (" + std::to_string(config_.replay.capacity) +
                        ") must be at least the number of PEARL tasks, task variations (" +
                        std::to_string(num_keys_) + ")");
    }
    replay_ = std::make_unique<agents::ReplayBuffer>(config_.replay.capacity, facts_.obs_dim,
                                                     facts_.action_dim, num_keys_);
    encoder_replay_ = std::make_unique<agents::ReplayBuffer>(
        config_.replay.capacity, facts_.obs_dim, facts_.action_dim, num_keys_);
    replay_generator_ = rl::MakeGenerator(MixSeed(config_.experiment.seed, kReplayStream));
    obs_.assign(num_envs_ * facts_.obs_dim, 0.0f);
    unit_.assign(num_envs_ * facts_.action_dim, 0.0f);
  }

  int64_t rounds_per_iteration() const override {
    return learner_->config().episodes_per_iteration();
  }
  bool SupportsSplit() const override {
    return learner_->config().prior_episodes >= 1 &&
           rounds_per_iteration() > learner_->config().prior_episodes;
  }
  agents::Actor& actor() override { return learner_->AsActor(); }
  int64_t updates() const override { return learner_->num_updates(); }

  nlohmann::json TrainIteration(Collector& collector, int64_t first_round, int64_t step) override {
    const agents::PearlConfig& c = learner_->config();
    const int64_t rounds = rounds_per_iteration();
    const bool warming = step < config_.experiment.warmup_steps;
    double t_act = 0.0, t_env = 0.0, t_update = 0.0;
    EpisodeTotals prior_totals, posterior_totals;
    std::vector<int64_t> keys(num_envs_);
    for (int64_t k = 0; k < rounds; ++k) {
      collector.BeginRound(config_.experiment.seed, first_round + k, rounds, c.prior_episodes);
      // with a split, only the support rounds fill the encoder's buffer
      const bool to_encoder = !split_ || k < c.prior_episodes;
      if (k == 0) {
        std::set<int64_t> cleared;
        for (int64_t i = 0; i < num_envs_; ++i) {
          keys[i] = key_offset_[collector.env_tasks()[i]] +
                    collector.env_variations()[i] / group_size_;
          if (!warming && c.prior_episodes > 0 && cleared.insert(keys[i]).second) {
            encoder_replay_->ClearTask(keys[i]);
          }
        }
      }
      const Phase phase = warming || k < c.prior_episodes               ? Phase::kPrior
                          : k < c.prior_episodes + c.posterior_episodes ? Phase::kPosterior
                                                                        : Phase::kExtraPosterior;
      const torch::Tensor latent = Latents(phase, keys);
      EpisodeTotals& phase_totals = phase == Phase::kPrior ? prior_totals : posterior_totals;
      const int64_t d = facts_.obs_dim, a = facts_.action_dim;
      for (int64_t s = 0; s < round_length_; ++s) {
        const auto t0 = Clock::now();
        const auto current = collector.observations();
        std::copy(current.begin(), current.end(), obs_.begin());
        const torch::Tensor o = torch::from_blob(obs_.data(), {num_envs_, d}, torch::kFloat32);
        const torch::Tensor act =
            learner_->ActWithLatent(o, latent, /*deterministic=*/false, learner_->generator())
                .contiguous();
        std::copy(act.data_ptr<float>(), act.data_ptr<float>() + act.numel(), unit_.begin());
        const auto t1 = Clock::now();
        collector.Step(unit_, phase_totals);
        BatchedExecutor& exec = collector.executor();
        const auto next = exec.env_obs();
        const auto final_obs = exec.final_env_obs();
        const auto rewards = exec.rewards();
        const auto terminated = exec.terminated();
        const auto truncated = exec.truncated();
        for (int64_t i = 0; i < num_envs_; ++i) {
          const bool ended = terminated[i] || truncated[i];
          const float* next_row = (ended ? final_obs.data() : next.data()) + i * d;
          const std::span<const float> obs_row{obs_.data() + i * d, static_cast<size_t>(d)};
          const std::span<const float> action_row{unit_.data() + i * a, static_cast<size_t>(a)};
          const std::span<const float> next_span{next_row, static_cast<size_t>(d)};
          replay_->Add(keys[i], obs_row, action_row, rewards[i], next_span, terminated[i]);
          if (phase != Phase::kExtraPosterior && to_encoder) {
            encoder_replay_->Add(keys[i], obs_row, action_row, rewards[i], next_span,
                                 terminated[i]);
          }
        }
        const auto t2 = Clock::now();
        t_act += Seconds(t1 - t0);
        t_env += Seconds(t2 - t1);
      }
    }
    MetricMeans means;
    if (!warming) {
      const auto t0 = Clock::now();
      std::vector<int64_t> ready;
      for (int64_t key = 0; key < num_keys_; ++key) {
        if (replay_->size(key) > 0 && encoder_replay_->size(key) > 0) ready.push_back(key);
      }
      std::vector<int64_t> batch_keys(c.meta_batch);
      for (int64_t u = 0; u < c.updates_per_iteration; ++u) {
        const torch::Tensor pick = torch::randint(static_cast<int64_t>(ready.size()),
                                                  {c.meta_batch}, replay_generator_, torch::kInt64);
        const int64_t* picked = pick.data_ptr<int64_t>();
        for (int64_t j = 0; j < c.meta_batch; ++j) batch_keys[j] = ready[picked[j]];
        const agents::Batch& context =
            encoder_replay_->SampleTasks(batch_keys, c.embedding_batch_size, replay_generator_);
        const agents::Batch& rl = replay_->SampleTasks(batch_keys, c.batch_size, replay_generator_);
        means.Add(learner_->Update(context, rl, c.meta_batch));
      }
      t_update = Seconds(Clock::now() - t0);
    }
    const bool has_success = facts_.success_index >= 0;
    nlohmann::json row = {
        {"time_act_s", t_act},
        {"time_env_s", t_env},
        {"time_update_s", t_update},
        {"buffer_size", replay_->size()},
    };
    EpisodeTotals all = prior_totals;
    all.Add(posterior_totals);
    all.WriteTo(row, has_success);
    auto mean_return = [](const EpisodeTotals& t) {
      return t.episodes > 0 ? nlohmann::json(t.return_sum / t.episodes) : nlohmann::json();
    };
    row["train_return_prior"] = mean_return(prior_totals);
    row["train_return_posterior"] = mean_return(posterior_totals);
    if (has_success) {
      auto rate = [](const EpisodeTotals& t) {
        return t.episodes > 0 ? nlohmann::json(t.success_sum / t.episodes) : nlohmann::json();
      };
      row["train_success_prior"] = rate(prior_totals);
      row["train_success_posterior"] = rate(posterior_totals);
    }
    means.WriteTo(row);
    return row;
  }

  void Save(const std::filesystem::path& dir, nlohmann::json& /*state*/) const override {
    WriteArchive(dir / "learner.pt", [&](torch::serialize::OutputArchive& archive) {
      learner_->Save(archive);
      archive.write("replay_generator", rl::GeneratorState(replay_generator_));
    });
    replay_->SaveFile(dir / "replay.bin");
    encoder_replay_->SaveFile(dir / "encoder_replay.bin");
  }

  void Load(const std::filesystem::path& dir, const nlohmann::json& /*state*/) override {
    ReadArchive(dir / "learner.pt", [&](torch::serialize::InputArchive& archive) {
      learner_->Load(archive);
      torch::Tensor replay_state;
      archive.read("replay_generator", replay_state);
      rl::SetGeneratorState(replay_generator_, replay_state);
    });
    replay_->LoadFile(dir / "replay.bin");
    encoder_replay_->LoadFile(dir / "encoder_replay.bin");
  }

  void LoadPolicy(const std::filesystem::path& dir) override {
    ReadArchive(dir / "learner.pt",
                [&](torch::serialize::InputArchive& archive) { learner_->Load(archive); });
  }

 private:
  // One z per env for a round of this phase: from the prior, or from the
  // posterior of a context sample of the env's key (the prior where its
  // encoder partition is still empty).
  torch::Tensor Latents(Phase phase, const std::vector<int64_t>& keys) {
    at::Generator& generator = learner_->generator();
    agents::LatentBelief belief = learner_->Prior(num_envs_);
    if (phase != Phase::kPrior) {
      std::vector<int64_t> with_data, rows;
      for (int64_t i = 0; i < num_envs_; ++i) {
        if (encoder_replay_->size(keys[i]) > 0) {
          with_data.push_back(keys[i]);
          rows.push_back(i);
        }
      }
      if (!with_data.empty()) {
        const int64_t ce = learner_->config().embedding_batch_size;
        const agents::Batch& context = encoder_replay_->SampleTasks(with_data, ce, generator);
        c10::InferenceMode inference;
        const agents::LatentBelief posterior =
            learner_->Posterior(agents::PearlLearner::ContextRows(context).reshape(
                {static_cast<int64_t>(with_data.size()), ce, -1}));
        const torch::Tensor index = torch::tensor(rows, torch::kInt64);
        belief.mean.index_copy_(0, index, posterior.mean);
        belief.var.index_copy_(0, index, posterior.var);
      }
    }
    return agents::PearlLearner::SampleLatent(belief, generator);
  }

  const TrainConfig& config_;
  EnvFacts facts_;
  int64_t num_envs_, round_length_;
  std::unique_ptr<agents::PearlLearner> learner_;
  std::vector<int64_t> key_offset_;
  int64_t num_keys_ = 0;
  bool split_ = false;      // a support/query split: keys are (task, group)
  int64_t group_size_ = 1;  // variations per key
  std::unique_ptr<agents::ReplayBuffer> replay_;
  std::unique_ptr<agents::ReplayBuffer> encoder_replay_;
  mutable at::Generator replay_generator_;
  std::vector<float> obs_, unit_;
};

}  // namespace

std::unique_ptr<Algorithm> MakePearlAlgorithm(const AlgorithmSetup& setup) {
  return std::make_unique<PearlAlgorithm>(setup);
}

}  // namespace manyworlds::experiments
