#include "manyworlds/core/policy.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "manyworlds/core/error.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/core/success.h"

namespace manyworlds {

nlohmann::json RolloutSummary::ToJson() const {
  // nlohmann::json keeps object keys sorted and prints doubles with the
  // shortest round-trip form, so the text is deterministic.
  const bool has_success = success_rate >= 0.0;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& e : episodes) {
    list.push_back({{"return", e.episode_return},
                    {"length", e.length},
                    {"success", e.success >= 0 ? nlohmann::json(e.success) : nlohmann::json()}});
  }
  return {{"episodes", std::move(list)},
          {"mean_return", mean_return},
          {"success_rate", has_success ? nlohmann::json(success_rate) : nlohmann::json()}};
}

RolloutSummary Rollout(Env& env, Policy& policy, int episodes, int64_t max_steps_per_episode) {
  if (episodes < 0) {
    throw ConfigError("Rollout on env '" + env.id() + "': episodes must be >= 0, got " +
                      std::to_string(episodes));
  }
  if (max_steps_per_episode < 1) {
    throw ConfigError("Rollout on env '" + env.id() +
                      "': max_steps_per_episode must be >= 1, got " +
                      std::to_string(max_steps_per_episode));
  }
  const EnvSpec& spec = env.spec();
  const int success_index = spec.InfoIndex("success");
  const bool has_limit = spec.max_episode_steps > 0;

  // Buffers are allocated once; the view overloads allocate nothing per step.
  std::vector<float> env_obs(spec.env_obs_space.flat_size());
  std::vector<float> task_obs(spec.task_obs_space.flat_size());
  std::vector<float> info(spec.info_fields.size());
  std::vector<float> action(spec.action_space.flat_size());
  std::vector<uint8_t> pixels(spec.pixel_space.flat_size());
  float reward = 0.0f;
  bool terminated = false, truncated = false;
  const StepView step_view{env_obs, task_obs, &reward, &terminated, &truncated, info, pixels};

  RolloutSummary summary;
  summary.episodes.reserve(episodes);
  double total_return = 0.0, total_length = 0.0;
  int successes = 0;
  for (int episode = 0; episode < episodes; ++episode) {
    policy.BeginEpisode();
    env.Reset(ObsView{env_obs, task_obs, pixels});
    EpisodeStats stats;
    stats.success = success_index >= 0 ? 0 : -1;
    while (true) {
      policy.Act(env_obs, task_obs, action);
      env.Step(action, step_view);
      stats.episode_return += reward;
      ++stats.length;
      if (success_index >= 0 && IsSuccess(info[success_index])) stats.success = 1;
      stats.terminated = terminated;
      stats.truncated = truncated;
      if (terminated || truncated) break;
      if (!has_limit && stats.length >= max_steps_per_episode) {
        stats.truncated = true;
        break;
      }
    }
    total_return += stats.episode_return;
    total_length += static_cast<double>(stats.length);
    successes += stats.success > 0 ? 1 : 0;
    summary.episodes.push_back(stats);
  }
  if (episodes > 0) {
    summary.mean_return = total_return / episodes;
    summary.mean_length = total_length / episodes;
  }
  if (success_index >= 0) {
    summary.success_rate = episodes > 0 ? static_cast<double>(successes) / episodes : 0.0;
  }
  return summary;
}

std::vector<EpisodeStats> RunEpisodes(Env& env, const EnvMaker& make_env, int num_episodes,
                                      int num_threads, const EpisodeSetup& prepare,
                                      int64_t max_steps_per_episode) {
  if (num_episodes < 0 || num_threads < 1 || num_threads > kMaxThreads) {
    throw ConfigError("RunEpisodes on env '" + env.id() +
                      "': episodes must be >= 0 and threads in [1, " +
                      std::to_string(kMaxThreads) + "], got " +
                      std::to_string(num_episodes) + " and " + std::to_string(num_threads));
  }
  std::vector<EpisodeStats> stats(static_cast<size_t>(num_episodes));
  std::atomic<int> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  int error_episode = num_episodes;
  // Called inside a catch block: keeps the error of the first failing
  // episode, as one thread would, and stops handing out episodes.
  auto fail = [&](int episode) {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (episode < error_episode) {
      error_episode = episode;
      error = std::current_exception();
    }
    next = num_episodes;
  };
  auto work = [&](Env& e) {
    for (int i = next++; i < num_episodes; i = next++) {
      try {
        const std::unique_ptr<Policy> policy = prepare(e, i);
        stats[static_cast<size_t>(i)] = Rollout(e, *policy, 1, max_steps_per_episode).episodes[0];
      } catch (...) {
        fail(i);
      }
    }
  };
  std::vector<std::thread> threads;
  const int extra = std::min(num_threads, std::max(num_episodes, 1)) - 1;
  // a thread the system will not start ends the run with an error, after the started ones
  // (a joinable std::thread destroyed by the exception would abort the program)
  const auto join_all = [&] {
    for (std::thread& t : threads) t.join();
  };
  for (int t = 0; t < extra; ++t) {
    try {
      threads.emplace_back([&] {
        std::unique_ptr<Env> own;
        try {
          own = make_env();
        } catch (...) {
          fail(num_episodes - 1);  // an env that cannot be made: reported unless one failed
          return;
        }
        work(*own);
      });
    } catch (const std::exception& e) {
      next = num_episodes;
      join_all();
      ThrowThreadsNotStarted(e, t + 1, extra + 1, "the number of threads");
    }
  }
  work(env);
  join_all();
  if (error) std::rethrow_exception(error);
  return stats;
}

RolloutSummary Summarize(std::vector<EpisodeStats> episodes) {
  return MergeGroups({GroupRollout{"", RolloutSummary{std::move(episodes)}}});
}

std::vector<GroupRollout> RolloutTaskGroups(Env& env, Policy& policy,
                                            const std::vector<TaskGroup>& groups, int per_group) {
  std::vector<GroupRollout> results;
  results.reserve(groups.size());
  for (const TaskGroup& group : groups) {
    const size_t count = per_group <= 0 ? group.states.size()
                                        : std::min(group.states.size(),
                                                   static_cast<size_t>(per_group));
    GroupRollout result{group.name, {}};
    for (size_t i = 0; i < count; ++i) {
      env.SetTaskState(group.states[i]);
      RolloutSummary one = Rollout(env, policy, 1);
      result.summary.episodes.push_back(one.episodes.front());
    }
    result.summary = MergeGroups({result});
    results.push_back(std::move(result));
  }
  return results;
}

RolloutSummary MergeGroups(const std::vector<GroupRollout>& groups) {
  RolloutSummary merged;
  double total_return = 0.0, total_length = 0.0;
  int successes = 0;
  bool has_success = true;
  for (const GroupRollout& group : groups) {
    for (const EpisodeStats& e : group.summary.episodes) {
      merged.episodes.push_back(e);
      total_return += e.episode_return;
      total_length += static_cast<double>(e.length);
      successes += e.success > 0 ? 1 : 0;
      has_success = has_success && e.success >= 0;
    }
  }
  const double n = static_cast<double>(merged.episodes.size());
  if (n > 0) {
    merged.mean_return = total_return / n;
    merged.mean_length = total_length / n;
  }
  merged.success_rate = has_success && n > 0 ? successes / n : -1.0;
  return merged;
}

nlohmann::json GroupsToJson(const std::vector<GroupRollout>& groups) {
  nlohmann::json json = MergeGroups(groups).ToJson();
  nlohmann::json per_task = nlohmann::json::array();
  for (const GroupRollout& group : groups) {
    const RolloutSummary& s = group.summary;
    per_task.push_back(
        {{"task", group.name},
         {"episodes", s.episodes.size()},
         {"mean_return", s.mean_return},
         {"success_rate", s.success_rate >= 0 ? nlohmann::json(s.success_rate) : nlohmann::json()}});
  }
  json["per_task"] = std::move(per_task);
  return json;
}

}  // namespace manyworlds
