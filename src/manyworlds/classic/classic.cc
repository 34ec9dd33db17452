#include "manyworlds/classic/classic.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "manyworlds/classic/acrobot.h"
#include "manyworlds/classic/bandit.h"
#include "manyworlds/classic/cartpole.h"
#include "manyworlds/classic/point_nav.h"
#include "manyworlds/classic/point_nav_sparse.h"
#include "manyworlds/classic/tabular_mdp.h"
#include "manyworlds/classic/two_goal_maze.h"

namespace manyworlds {
namespace {

constexpr const char* kFamily = "classic";

OptionSpec HideTaskOption() {
  return {"hide_task", OptionType::kBool, false,
          "if true the task observation is all zeros (meta-RL: infer the task)"};
}

OptionSpec HorizonOption(int64_t default_steps) {
  return {"horizon", OptionType::kInt, default_steps,
          "episode length in steps (>= 1); episodes are truncated there"};
}

void Add(Registry& registry, std::string id, std::string description,
         std::vector<OptionSpec> options, EnvFactory factory) {
  options.push_back(HideTaskOption());
  registry.Add(EnvRegistration{std::move(id), kFamily, std::move(description), std::move(options),
                               std::move(factory)});
}

}  // namespace

void RegisterClassicSuite(Registry& registry) {
  using classic::AcrobotEnv;
  using classic::BanditEnv;
  using classic::CartPoleEnv;
  using classic::PointNavEnv;
  using classic::PointNavSparseEnv;
  using classic::TabularMdpEnv;
  using classic::TwoGoalMazeEnv;

  Add(registry, BanditEnv::kId, "Bernoulli multi-armed bandit; task = arm probabilities",
      {{"n_arms", OptionType::kInt, 5, "number of arms, in [2, 10000]"}, HorizonOption(100)},
      [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<BanditEnv>(
            BanditEnv::Config{o.Int("n_arms"), o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, TabularMdpEnv::kId,
      "Random tabular MDP; task = reward means and transition probabilities",
      {{"n_states", OptionType::kInt, 4, "number of states, in [1, 100]"},
       {"n_actions", OptionType::kInt, 5, "number of actions, in [1, 100]"},
       HorizonOption(10)},
      [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<TabularMdpEnv>(TabularMdpEnv::Config{
            o.Int("n_states"), o.Int("n_actions"), o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, TwoGoalMazeEnv::kId, "Grid T-maze with two goals; task = which goal pays",
      {HorizonOption(50)}, [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<TwoGoalMazeEnv>(
            TwoGoalMazeEnv::Config{o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, CartPoleEnv::kId,
      "Cart-pole; task = gravity, cart and pole mass, pole length, push force",
      {HorizonOption(500)}, [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<CartPoleEnv>(
            CartPoleEnv::Config{o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, AcrobotEnv::kId, "Acrobot swing-up; task = link lengths, masses, torque sign",
      {HorizonOption(500)}, [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<AcrobotEnv>(
            AcrobotEnv::Config{o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, PointNavEnv::kId, "2-D point navigation, dense reward; task = goal in a square",
      {{"goal_range", OptionType::kFloat, 0.5,
        "goals are drawn from U[-goal_range, goal_range]^2; in (0, 100]"},
       HorizonOption(100)},
      [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<PointNavEnv>(
            PointNavEnv::Config{o.Float("goal_range"), o.Int("horizon"), o.Bool("hide_task")});
      });

  Add(registry, PointNavSparseEnv::kId,
      "2-D point navigation, sparse reward; task = goal on the unit half-circle",
      {{"goal_radius", OptionType::kFloat, 0.2,
        "reward 1 within this distance of the goal; in (0, 2]"},
       HorizonOption(30)},
      [](const Options& o) -> std::unique_ptr<Env> {
        return std::make_unique<PointNavSparseEnv>(PointNavSparseEnv::Config{
            o.Float("goal_radius"), o.Int("horizon"), o.Bool("hide_task")});
      });
}

}  // namespace manyworlds
