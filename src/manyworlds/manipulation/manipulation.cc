#include "manyworlds/manipulation/manipulation.h"

#include <functional>

#include "manyworlds/core/error.h"
#include "manyworlds/manipulation/pick_place/basketball.h"
#include "manyworlds/manipulation/benchmark.h"
#include "manyworlds/manipulation/button/button_press_topdown.h"
#include "manyworlds/manipulation/coffee/coffee_button.h"
#include "manyworlds/manipulation/coffee/coffee_mug.h"
#include "manyworlds/manipulation/container/bin_picking.h"
#include "manyworlds/manipulation/container/box_close.h"
#include "manyworlds/manipulation/door/door_close.h"
#include "manyworlds/manipulation/door/door_open.h"
#include "manyworlds/manipulation/drawer/drawer.h"
#include "manyworlds/manipulation/hole/hand_insert.h"
#include "manyworlds/manipulation/hole/pick_out_of_hole.h"
#include "manyworlds/manipulation/rotary/lever_pull.h"
#include "manyworlds/manipulation/peg/nut.h"
#include "manyworlds/manipulation/peg/peg_unplug_side.h"
#include "manyworlds/manipulation/peg/peg_insert_side.h"
#include "manyworlds/manipulation/pick_place/pick_place.h"
#include "manyworlds/manipulation/push/push.h"
#include "manyworlds/manipulation/reach/reach.h"
#include "manyworlds/manipulation/rotary/dial_turn.h"
#include "manyworlds/manipulation/door/door_lock.h"
#include "manyworlds/manipulation/rotary/faucet.h"
#include "manyworlds/manipulation/pick_place/shelf_place.h"
#include "manyworlds/manipulation/sweep/sweep.h"
#include "manyworlds/manipulation/plate_slide/plate_slide.h"
#include "manyworlds/manipulation/button/buttons.h"
#include "manyworlds/manipulation/handle/handles.h"
#include "manyworlds/manipulation/push/push_back.h"
#include "manyworlds/manipulation/push/soccer.h"
#include "manyworlds/manipulation/tool/hammer.h"
#include "manyworlds/manipulation/tool/stick.h"
#include "manyworlds/manipulation/pick_place/pick_place_wall.h"
#include "manyworlds/manipulation/push/push_wall.h"
#include "manyworlds/manipulation/window/window.h"

namespace manyworlds::manipulation {
namespace {

// One row per task: adding a task means adding a row here.
struct TaskEntry {
  std::function<SawyerTaskConfig()> config;
  std::function<std::unique_ptr<Env>(SawyerOptions)> make_env;
  std::function<std::unique_ptr<Policy>()> make_policy;
};

template <typename Task, typename ScriptedPolicy>
TaskEntry Entry() {
  return {&Task::Config,
          [](SawyerOptions options) { return std::make_unique<Task>(options); },
          [] { return std::make_unique<ScriptedPolicy>(); }};
}

// A row for one variant of a parameterised task: Task(variant, options),
// Task::Config(variant), ScriptedPolicy(variant).
template <typename Task, typename ScriptedPolicy, typename Variant>
TaskEntry Entry(Variant variant) {
  return {[variant] { return Task::Config(variant); },
          [variant](SawyerOptions options) { return std::make_unique<Task>(variant, options); },
          [variant] { return std::make_unique<ScriptedPolicy>(variant); }};
}

const std::vector<TaskEntry>& Tasks() {
  static const std::vector<TaskEntry> tasks = {
      Entry<Reach, ReachScriptedPolicy>(ReachVariant::kOpen),
      Entry<Push, PushScriptedPolicy>(),
      Entry<PickPlace, PickPlaceScriptedPolicy>(),
      Entry<DoorOpen, DoorOpenScriptedPolicy>(),
      Entry<DrawerOpen, DrawerOpenScriptedPolicy>(),
      Entry<DrawerClose, DrawerCloseScriptedPolicy>(),
      Entry<ButtonPressTopdown, ButtonPressTopdownScriptedPolicy>(),
      Entry<PegInsertSide, PegInsertSideScriptedPolicy>(),
      Entry<Window, WindowScriptedPolicy>(WindowMotion::kOpen),
      Entry<Window, WindowScriptedPolicy>(WindowMotion::kClose),
      Entry<Sweep, SweepScriptedPolicy>(SweepVariant::kEdge),
      Entry<Basketball, BasketballScriptedPolicy>(),
      Entry<DoorClose, DoorCloseScriptedPolicy>(),
      Entry<ShelfPlace, ShelfPlaceScriptedPolicy>(),
      Entry<Sweep, SweepScriptedPolicy>(SweepVariant::kInto),
      Entry<LeverPull, LeverPullScriptedPolicy>(),
      Entry<Reach, ReachScriptedPolicy>(ReachVariant::kWall),
      Entry<PushWall, PushWallScriptedPolicy>(),
      Entry<PickPlaceWall, PickPlaceWallScriptedPolicy>(),
      Entry<PushBack, PushBackScriptedPolicy>(),
      Entry<PlateSlide, PlateSlideScriptedPolicy>(),
      Entry<PlateSlideSide, PlateSlideScriptedPolicy>(),
      Entry<PlateSlideBack, PlateSlideScriptedPolicy>(),
      Entry<PlateSlideBackSide, PlateSlideScriptedPolicy>(),
      Entry<Soccer, SoccerScriptedPolicy>(),
      Entry<FaucetOpen, FaucetScriptedPolicy>(),
      Entry<FaucetClose, FaucetScriptedPolicy>(),
      Entry<DialTurn, DialTurnScriptedPolicy>(),
      Entry<DoorLock, DoorLockScriptedPolicy>(),
      Entry<DoorUnlock, DoorUnlockScriptedPolicy>(),
      Entry<ButtonPress, ButtonPressScriptedPolicy>(),
      Entry<ButtonPressWall, ButtonPressWallScriptedPolicy>(),
      Entry<ButtonPressTopdownWall, ButtonPressTopdownWallScriptedPolicy>(),
      Entry<HandlePress, HandlePressScriptedPolicy>(),
      Entry<HandlePressSide, HandlePressScriptedPolicy>(),
      Entry<HandlePull, HandlePullScriptedPolicy>(),
      Entry<HandlePullSide, HandlePullSideScriptedPolicy>(),
      Entry<CoffeeButton, CoffeeButtonScriptedPolicy>(),
      Entry<CoffeePush, CoffeeMugScriptedPolicy>(),
      Entry<CoffeePull, CoffeeMugScriptedPolicy>(),
      Entry<HandInsert, HandInsertScriptedPolicy>(),
      Entry<PickOutOfHole, PickOutOfHoleScriptedPolicy>(),
      Entry<BinPicking, BinPickingScriptedPolicy>(),
      Entry<BoxClose, BoxCloseScriptedPolicy>(),
      Entry<Assembly, AssemblyScriptedPolicy>(),
      Entry<Disassemble, DisassembleScriptedPolicy>(),
      Entry<PegUnplugSide, PegUnplugSideScriptedPolicy>(),
      Entry<Hammer, HammerScriptedPolicy>(),
      Entry<StickPush, StickPushScriptedPolicy>(),
      Entry<StickPull, StickPullScriptedPolicy>(),
  };
  return tasks;
}

std::vector<OptionSpec> SuiteOptions() {
  return {
      {"goal_observable", OptionType::kBool, true,
       "goal position in obs[36:39] and the task observation (false: zeros, meta-RL setting)"},
      {"throw_on_sim_warning", OptionType::kBool, false,
       "throw on MuJoCo warnings during a step instead of truncating the episode"},
      {"reward_version", OptionType::kString, "v2",
       "Meta-World's reward_function_version: v2 (v3's default, in [0, 10]) or v1 (the "
       "original shaped reward)",
       {"v2", "v1"}},
  };
}

}  // namespace

void RegisterManipulationSuite(Registry& registry) {
  for (const TaskEntry& task : Tasks()) {
    const SawyerTaskConfig config = task.config();
    registry.Add({config.id, "manipulation", config.description, SuiteOptions(),
                  [make = task.make_env](const Options& options) {
                    SawyerOptions sawyer;
                    sawyer.goal_observable = options.Bool("goal_observable");
                    sawyer.throw_on_sim_warning = options.Bool("throw_on_sim_warning");
                    sawyer.reward_version = options.String("reward_version") == "v1"
                                                ? RewardVersion::kV1
                                                : RewardVersion::kV2;
                    return make(sawyer);
                  }});
  }
  RegisterBenchmarks(registry);
}

std::unique_ptr<SawyerTask> MakeSawyerTask(std::string_view task_id, SawyerOptions options) {
  for (const TaskEntry& task : Tasks()) {
    if (task.config().id == task_id) {
      return std::unique_ptr<SawyerTask>(static_cast<SawyerTask*>(task.make_env(options).release()));
    }
  }
  throw ConfigError("unknown manipulation task '" + std::string(task_id) + "'" +
                    SuggestNearest(task_id, ManipulationTaskIds()));
}

std::vector<std::string> ManipulationTaskIds() {
  std::vector<std::string> ids;
  for (const TaskEntry& task : Tasks()) ids.push_back(task.config().id);
  return ids;
}

std::unique_ptr<Policy> MakeScriptedPolicy(std::string_view task_id) {
  for (const TaskEntry& task : Tasks()) {
    if (task.config().id == task_id) return task.make_policy();
  }
  throw ConfigError("no scripted manipulation policy for '" + std::string(task_id) + "'" +
                    SuggestNearest(task_id, ManipulationTaskIds()));
}

}  // namespace manyworlds::manipulation
