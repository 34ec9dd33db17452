#include "manyworlds/dmc/dmc.h"

#include <memory>

#include "manyworlds/dmc/dmc_env.h"

namespace manyworlds {

void RegisterDmcSuite(Registry& registry) {
  using dmc::DmcEnv;
  using dmc::DmcTask;
  using dmc::Variation;
  const std::pair<DmcTask, Variation> envs[] = {
      {DmcTask::kFingerSpin, Variation::kNone},
      {DmcTask::kCheetahRun, Variation::kNone},
      {DmcTask::kWalkerWalk, Variation::kNone},
      {DmcTask::kFingerSpin, Variation::kFingerSize},
      {DmcTask::kCheetahRun, Variation::kCheetahTorsoLength},
      {DmcTask::kWalkerWalk, Variation::kWalkerFriction},
      {DmcTask::kWalkerWalk, Variation::kWalkerFootLength}};
  for (const auto& entry : envs) {
    // plain copies: some compilers refuse to capture structured bindings in a lambda
    const DmcTask task = entry.first;
    const Variation variation = entry.second;
    std::vector<OptionSpec> options = {{"throw_on_sim_warning", OptionType::kBool, false,
                                        "throw on a MuJoCo warning instead of ending the episode"}};
    const bool has_split = variation == Variation::kFingerSize;
    if (has_split) {
      options.push_back(
          {"split",
           OptionType::kString,
           "all",
           "'all': sample the 10 variants, evaluate each; 'mtrl': MTRL's split, sample the "
           "train variants 3, 4, 7, 8, evaluate groups train, interpolation (5, 6) and "
           "extrapolation (2, 9)",
           {"all", "mtrl"}});
    }
    registry.Add(EnvRegistration{
        DmcEnv::IdOf(task, variation), "dmc", DmcEnv::Description(task, variation),
        std::move(options), [task, variation, has_split](const Options& o) -> std::unique_ptr<Env> {
          DmcEnv::Config config{.task = task, .variation = variation};
          if (has_split && o.String("split") == "mtrl") config.split = dmc::Split::kMtrl;
          config.throw_on_sim_warning = o.Bool("throw_on_sim_warning");
          return std::make_unique<DmcEnv>(config);
        }});
  }
}

}  // namespace manyworlds
