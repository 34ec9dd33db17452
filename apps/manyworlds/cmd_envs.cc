// manyworlds envs [--json]: every registered env with its spaces and options.
#include <iostream>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ",") + item;
  return out.empty() ? "-" : out;
}

nlohmann::json OptionJson(const OptionSpec& option) {
  nlohmann::json j = {{"name", option.name},
                      {"type", OptionTypeName(option.type)},
                      {"default", option.default_value},
                      {"doc", option.doc}};
  if (!option.choices.empty()) j["choices"] = option.choices;
  return j;
}

void RunEnvs(bool json) {
  const Registry& registry = DefaultRegistry();
  nlohmann::json all = nlohmann::json::array();
  Table table({"id", "family", "action", "env obs", "task obs", ">max steps", "info",
               "description"});
  for (const auto& entry : registry.entries()) {
    // the spec (spaces, limits) belongs to an instance: build one with defaults
    const EnvSpec spec = registry.Make(entry.id)->spec();
    if (json) {
      nlohmann::json options = nlohmann::json::array();
      for (const auto& option : entry.options) options.push_back(OptionJson(option));
      all.push_back({{"id", entry.id},
                     {"family", entry.family},
                     {"description", entry.description},
                     {"action_space", spec.action_space.ToJson()},
                     {"env_obs_space", spec.env_obs_space.ToJson()},
                     {"task_obs_space", spec.task_obs_space.ToJson()},
                     {"max_episode_steps", spec.max_episode_steps},
                     {"info_fields", spec.info_fields},
                     {"options", options}});
    } else {
      table.AddRow({entry.id, entry.family, spec.action_space.ToString(),
                    spec.env_obs_space.ToString(), spec.task_obs_space.ToString(),
                    spec.max_episode_steps > 0 ? std::to_string(spec.max_episode_steps) : "none",
                    Join(spec.info_fields), entry.description});
    }
  }
  if (json) {
    PrintJson(all);
  } else {
    table.Print(std::cout);
  }
}

}  // namespace

void AddEnvsCommand(CLI::App& app, CommandContext& /*context*/) {
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("envs", "List every registered environment");
  cmd->add_flag("--json", *json, "print JSON (with every option: name, type, default, doc)");
  cmd->callback([json] { RunEnvs(*json); });
}

}  // namespace manyworlds::cli
