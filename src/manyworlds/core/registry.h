// The environment registry: make("id", options).
//
// Registration is explicit: each suite has a Register<Suite>(Registry&)
// function, and manyworlds/envs/all.h assembles the default registry. Options
// are typed and documented; unknown ids and unknown options are errors that
// suggest the nearest valid names.
#ifndef MANYWORLDS_CORE_REGISTRY_H_
#define MANYWORLDS_CORE_REGISTRY_H_

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"

namespace manyworlds {

enum class OptionType { kInt, kFloat, kBool, kString };

struct OptionSpec {
  std::string name;
  OptionType type = OptionType::kInt;
  nlohmann::json default_value;
  std::string doc;
  // kString only: the allowed values (empty: any string).
  std::vector<std::string> choices = {};
  // kInt and kFloat: the allowed range, checked when the value is resolved (before the env is
  // made). Most envs check their own options in their factories; a range here is for options
  // the registry adds itself.
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

// Resolved option values: every declared option present with the right type.
class Options {
 public:
  Options(std::string env_id, nlohmann::json values)
      : env_id_(std::move(env_id)), values_(std::move(values)) {}

  int64_t Int(std::string_view name) const;
  double Float(std::string_view name) const;
  bool Bool(std::string_view name) const;
  std::string String(std::string_view name) const;
  const nlohmann::json& values() const { return values_; }

 private:
  const nlohmann::json& Get(std::string_view name) const;

  std::string env_id_;
  nlohmann::json values_;
};

using EnvFactory = std::function<std::unique_ptr<Env>(const Options&)>;

// What the registry options obs=pixels, pixel_width, pixel_height and camera ask for.
struct PixelSettings {
  int64_t width = 84;
  int64_t height = 84;
  std::string camera;  // empty: the env's default camera
  bool full_quality = false;  // shadows and multisampling as the model asks (slow)
};
// Wraps an env so that it renders pixel observations (sim::MakePixelObservation; core cannot
// render, so the default registry installs it).
using PixelWrapperFactory =
    std::function<std::unique_ptr<Env>(std::unique_ptr<Env>, const PixelSettings&)>;

struct EnvRegistration {
  std::string id;
  std::string family;  // e.g. "classic", "manipulation", "benchmark"
  std::string description;
  std::vector<OptionSpec> options;
  EnvFactory factory;
};

class Registry {
 public:
  // String option values are at most this long (a longer one is refused, not parsed).
  static constexpr size_t kMaxStringOptionChars = 4096;
  // Option every registration gets: override the env's episode limit.
  static constexpr std::string_view kMaxEpisodeStepsOption = "max_episode_steps";
  static constexpr int64_t kMaxEpisodeStepsLimit = 1000000;
  // Option every registration gets: end episodes at the first success
  // (TerminateOnSuccess; a ConfigError for envs without a `success` field).
  static constexpr std::string_view kTerminateOnSuccessOption = "terminate_on_success";
  // Options every registration gets: the recurrent meta-RL observation
  // (RecurrentMetaObservation, outermost) and the reward scale it uses.
  static constexpr std::string_view kRecurrentMetaObsOption = "recurrent_meta_obs";
  static constexpr std::string_view kRecurrentMetaObsScaleOption = "recurrent_meta_obs_reward_scale";
  // Options every registration gets: repeat each action k times (ActionRepeat, innermost) and
  // stack the last k env observations (FrameStack, outermost); 1 = off.
  static constexpr std::string_view kActionRepeatOption = "action_repeat";
  static constexpr std::string_view kFrameStackOption = "frame_stack";
  // Options every registration gets: pixel observations (obs=pixels: rendered frames in the
  // pixel channel, env_obs stays the state), their size and camera. Rendered after the action
  // repeat, stacked by frame_stack.
  static constexpr std::string_view kObsOption = "obs";
  static constexpr std::string_view kPixelWidthOption = "pixel_width";
  static constexpr std::string_view kPixelHeightOption = "pixel_height";
  static constexpr std::string_view kCameraOption = "camera";
  static constexpr std::string_view kPixelQualityOption = "pixel_quality";

  // The options above, which Add gives every registration (a registration may not declare them).
  static const std::vector<std::string_view>& ReservedOptions();

  // Throws ConfigError on a duplicate id or a reserved option.
  void Add(EnvRegistration registration);
  bool Contains(std::string_view id) const;
  // Throws ConfigError naming the nearest ids.
  const EnvRegistration& Find(std::string_view id) const;
  const std::vector<EnvRegistration>& entries() const { return entries_; }
  std::vector<std::string> Ids() const;
  // Installs what obs=pixels wraps an env with; without it obs=pixels is a ConfigError.
  void SetPixelWrapper(PixelWrapperFactory factory) { pixel_wrapper_ = std::move(factory); }

  // Checks names and types, fills defaults. String values are converted to
  // the declared type, so "n_arms=5" from a command line works.
  Options ResolveOptions(std::string_view id, const nlohmann::json& given) const;
  std::unique_ptr<Env> Make(std::string_view id,
                            const nlohmann::json& options = nlohmann::json::object()) const;

 private:
  std::vector<EnvRegistration> entries_;
  PixelWrapperFactory pixel_wrapper_;
};

// A value for an error message: at most 80 characters ("..." ends a cut one).
std::string ShortenForMessage(std::string text);

// Edit distance, for suggestions.
size_t EditDistance(std::string_view a, std::string_view b);
// " (did you mean 'x' or 'y'?)" for the closest candidates, or "" if none is
// close.
std::string SuggestNearest(std::string_view name, const std::vector<std::string>& candidates);
std::string OptionTypeName(OptionType type);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_REGISTRY_H_
