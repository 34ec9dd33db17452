#include "manyworlds/core/registry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "manyworlds/core/error.h"
#include "manyworlds/core/wrappers/action_repeat.h"
#include "manyworlds/core/wrappers/frame_stack.h"
#include "manyworlds/core/wrappers/recurrent_meta_obs.h"
#include "manyworlds/core/wrappers/terminate_on_success.h"

namespace manyworlds {
namespace {

std::string Shorten(std::string text) { return ShortenForMessage(std::move(text)); }

// A value for an error message: a scalar as JSON, a list or mapping by its size only (a
// deeply nested one printed in full overflowed the stack).
std::string Describe(const nlohmann::json& value) {
  if (value.is_array()) return "a list of " + std::to_string(value.size()) + " items";
  if (value.is_object()) return "a mapping of " + std::to_string(value.size()) + " keys";
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {  // JSON writes null
    const double x = value.get<double>();
    return std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf";
  }
  return Shorten(value.dump());
}

// Converts `value` to the declared type; throws ConfigError on failure.
nlohmann::json Coerce(std::string_view env_id, const OptionSpec& spec,
                      const nlohmann::json& value) {
  auto fail = [&](const std::string& why) -> nlohmann::json {
    throw ConfigError("env '" + std::string(env_id) + "': option '" + spec.name + "' " + why +
                      " (expected " + OptionTypeName(spec.type) + "; " + spec.doc + ")");
  };
  if (value.is_string() && spec.type != OptionType::kString) {
    const std::string text = value.get<std::string>();
    // only a scalar can be an option's value: nothing nested is kept
    const auto scalars_only = [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
      return depth == 0;
    };
    auto parsed = text.size() > 4096 ? nlohmann::json(nlohmann::json::value_t::discarded)
                                     : nlohmann::json::parse(text, scalars_only, false);
    if (text == "True" || text == "true") parsed = true;
    if (text == "False" || text == "false") parsed = false;
    if (parsed.is_discarded() || parsed.is_string() || parsed.is_structured()) {
      return fail("has value '" + Shorten(text) + "'");
    }
    return Coerce(env_id, spec, parsed);
  }
  switch (spec.type) {
    case OptionType::kInt:
      // JSON keeps integers in [2^63, 2^64) unsigned: converted to int64 they wrapped
      if (value.is_number_unsigned() &&
          value.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
        return fail("has value " + value.dump() + ", beyond the integers [-2^63, 2^63)");
      }
      if (value.is_number_integer() ||
          (value.is_number_float() && std::floor(value.get<double>()) == value.get<double>() &&
           std::abs(value.get<double>()) < 9e15)) {
        const int64_t number = value.is_number_integer()
                                   ? value.get<int64_t>()
                                   : static_cast<int64_t>(value.get<double>());
        if (static_cast<double>(number) < spec.min || static_cast<double>(number) > spec.max) {
          char range[96];
          std::snprintf(range, sizeof(range), ", outside [%.0f, %.0f]", spec.min, spec.max);
          return fail("has value " + Describe(value) + range);
        }
        return number;
      }
      return fail("has value " + Describe(value));
    case OptionType::kFloat:
      if (value.is_number() && std::isfinite(value.get<double>())) {
        const double number = value.get<double>();
        if (number < spec.min || number > spec.max) {
          char range[96];
          std::snprintf(range, sizeof(range), ", outside [%g, %g]", spec.min, spec.max);
          return fail("has value " + Describe(value) + range);
        }
        return number;
      }
      return fail("has value " + Describe(value));
    case OptionType::kBool:
      if (value.is_boolean()) return value.get<bool>();
      return fail("has value " + Describe(value));
    case OptionType::kString: {
      if (!value.is_string()) return fail("has value " + Describe(value));
      const auto text = value.get<std::string>();
      if (text.size() > Registry::kMaxStringOptionChars) {
        return fail("has a value of " + std::to_string(text.size()) + " characters, more than " +
                    std::to_string(Registry::kMaxStringOptionChars));
      }
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end()) {
        // a long list (mt1's 50 task names) is summarised: the nearest names and the count
        constexpr size_t kListed = 12;
        std::string allowed;
        for (size_t k = 0; k < std::min(kListed, spec.choices.size()); ++k) {
          allowed += (k > 0 ? ", " : "") + spec.choices[k];
        }
        if (spec.choices.size() > kListed) {
          allowed = "one of " + std::to_string(spec.choices.size()) + " names (" + allowed +
                    ", ...; `manyworlds envs --json` lists them)";
        }
        throw ConfigError("env '" + std::string(env_id) + "': option '" + spec.name +
                          "' has value '" + Shorten(text) + "'" +
                          SuggestNearest(Shorten(text), spec.choices) + ", allowed: " + allowed);
      }
      return text;
    }
  }
  return fail("has an unsupported type");
}

}  // namespace

std::string ShortenForMessage(std::string text) {
  if (text.size() > 80) text = text.substr(0, 77) + "...";
  return text;
}

std::string OptionTypeName(OptionType type) {
  switch (type) {
    case OptionType::kInt:
      return "int";
    case OptionType::kFloat:
      return "float";
    case OptionType::kBool:
      return "bool";
    case OptionType::kString:
      return "string";
  }
  return "?";
}

size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), 0);
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      const size_t cost = std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1;
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + cost});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string SuggestNearest(std::string_view name, const std::vector<std::string>& candidates) {
  std::vector<std::pair<size_t, std::string>> scored;
  for (const auto& c : candidates) {
    const size_t d = EditDistance(name, c);
    const bool contains = !name.empty() && (c.find(name) != std::string::npos ||
                                            name.find(c) != std::string_view::npos);
    // Close enough to be a typo, or one name contains the other.
    if (d <= std::max<size_t>(2, name.size() / 3) || contains) scored.emplace_back(d, c);
  }
  if (scored.empty()) return "";
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::string out = " (did you mean '" + scored[0].second + "'";
  for (size_t i = 1; i < std::min<size_t>(scored.size(), 3); ++i) {
    out += " or '" + scored[i].second + "'";
  }
  return out + "?)";
}

const nlohmann::json& Options::Get(std::string_view name) const {
  auto it = values_.find(name);
  if (it == values_.end()) {
    throw ConfigError("env '" + env_id_ + "' has no option '" + std::string(name) + "'");
  }
  return *it;
}

int64_t Options::Int(std::string_view name) const { return Get(name).get<int64_t>(); }
double Options::Float(std::string_view name) const { return Get(name).get<double>(); }
bool Options::Bool(std::string_view name) const { return Get(name).get<bool>(); }
std::string Options::String(std::string_view name) const {
  return Get(name).get<std::string>();
}

const std::vector<std::string_view>& Registry::ReservedOptions() {
  static const std::vector<std::string_view> names = {
      kMaxEpisodeStepsOption, kTerminateOnSuccessOption, kRecurrentMetaObsOption,
      kRecurrentMetaObsScaleOption, kActionRepeatOption, kFrameStackOption,
      kObsOption, kPixelWidthOption, kPixelHeightOption, kCameraOption, kPixelQualityOption};
  return names;
}

void Registry::Add(EnvRegistration registration) {
  if (Contains(registration.id)) {
    throw ConfigError("env id '" + registration.id + "' is registered twice");
  }
  for (const auto& option : registration.options) {
    const auto& reserved = ReservedOptions();
    if (std::find(reserved.begin(), reserved.end(), option.name) != reserved.end()) {
      throw ConfigError("env '" + registration.id + "' declares the reserved option '" +
                        option.name + "'");
    }
  }
  registration.options.push_back(
      {std::string(kMaxEpisodeStepsOption), OptionType::kInt, -1,
       "truncate episodes after this many steps, in [1, 1000000]; -1 keeps the env's own limit"});
  registration.options.push_back(
      {std::string(kTerminateOnSuccessOption), OptionType::kBool, false,
       "end an episode (terminated) at the first step whose `success` info is 1, as Meta-World "
       "v3's evaluation does; only for envs with a success field"});
  registration.options.push_back(
      {std::string(kRecurrentMetaObsOption), OptionType::kBool, false,
       "append the previous action, the scaled reward and the episode-end flag to the env "
       "observation, as Meta-World v3's recurrent meta-RL wrapper does (Box observations only)"});
  registration.options.push_back(
      {std::string(kRecurrentMetaObsScaleOption), OptionType::kFloat, 0.1,
       "the reward factor of recurrent_meta_obs (Meta-World v3: 1/10), in [-1000, 1000]: the "
       "scaled reward stays a finite float32",
       {}, -1000.0, 1000.0});
  registration.options.push_back(
      {std::string(kActionRepeatOption), OptionType::kInt, int64_t{1},
       "apply each action this many times, summing the rewards (MTEnv's DeepMind-Control suites: "
       "2); the episode limit, max_episode_steps included, counts the env's own steps",
       {}, 1.0, static_cast<double>(ActionRepeat::kMaxRepeat)});
  registration.options.push_back(
      {std::string(kFrameStackOption), OptionType::kInt, int64_t{1},
       "the env observation is the last this many observations, oldest first (MTEnv's "
       "DeepMind-Control suites: 3; Box observations only)",
       {}, 1.0, static_cast<double>(FrameStack::kMaxFrames)});
  registration.options.push_back(
      {std::string(kObsOption), OptionType::kString, "state",
       "what env_obs holds: 'state' (the env's vector) or 'pixels' (rendered uint8 RGB frames, "
       "channels first, in the pixel observation; the state stays readable beside them); "
       "pixels only for MuJoCo envs",
       {"state", "pixels"}});
  registration.options.push_back(
      {std::string(kPixelWidthOption), OptionType::kInt, int64_t{84},
       "width of pixel observations in pixels (MTEnv: 84)", {}, 1.0, 4096.0});
  registration.options.push_back(
      {std::string(kPixelHeightOption), OptionType::kInt, int64_t{84},
       "height of pixel observations in pixels (MTEnv: 84)", {}, 1.0, 4096.0});
  registration.options.push_back(
      {std::string(kCameraOption), OptionType::kString, "",
       "camera of pixel observations: a preset (front, top, side, gripper) or a camera of the "
       "model; empty: the env's default (`manyworlds envs --describe ID`)"});
  registration.options.push_back(
      {std::string(kPixelQualityOption), OptionType::kString, "fast",
       "'fast': pixel observations without shadows or multisampling (about 10x faster in "
       "software rendering); 'full': as the model asks, as dm_control renders",
       {"fast", "full"}});
  entries_.push_back(std::move(registration));
}

bool Registry::Contains(std::string_view id) const {
  return std::any_of(entries_.begin(), entries_.end(),
                     [&](const EnvRegistration& r) { return r.id == id; });
}

const EnvRegistration& Registry::Find(std::string_view id) const {
  for (const auto& r : entries_) {
    if (r.id == id) return r;
  }
  throw ConfigError("unknown env id '" + std::string(id) + "'" + SuggestNearest(id, Ids()) +
                    "; run `manyworlds envs` to list all " + std::to_string(entries_.size()) +
                    " ids");
}

std::vector<std::string> Registry::Ids() const {
  std::vector<std::string> ids;
  for (const auto& r : entries_) ids.push_back(r.id);
  return ids;
}

Options Registry::ResolveOptions(std::string_view id, const nlohmann::json& given) const {
  const EnvRegistration& registration = Find(id);
  if (!given.is_null() && !given.is_object()) {
    throw ConfigError("env '" + registration.id + "': options must be a key/value object, got " +
                      Describe(given));
  }
  std::vector<std::string> names;
  for (const auto& o : registration.options) names.push_back(o.name);
  nlohmann::json resolved = nlohmann::json::object();
  for (const auto& o : registration.options) resolved[o.name] = o.default_value;
  if (given.is_object()) {
    for (const auto& [key, value] : given.items()) {
      const std::string& name = key;  // clang 14 cannot capture a structured binding
      auto spec = std::find_if(registration.options.begin(), registration.options.end(),
                               [&](const OptionSpec& o) { return o.name == name; });
      if (spec == registration.options.end()) {
        std::string all;
        for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
        throw ConfigError("env '" + registration.id + "' has no option '" + key + "'" +
                          SuggestNearest(key, names) + "; its options are: " + all);
      }
      resolved[key] = Coerce(registration.id, *spec, value);
    }
  }
  return Options(registration.id, std::move(resolved));
}

std::unique_ptr<Env> Registry::Make(std::string_view id, const nlohmann::json& options) const {
  const EnvRegistration& registration = Find(id);
  Options resolved = ResolveOptions(id, options);
  std::unique_ptr<Env> env = registration.factory(resolved);
  const int64_t limit = resolved.Int(kMaxEpisodeStepsOption);
  // 0 ("no limit") is refused here: trainers, rollouts and evaluations count
  // on every episode ending. The C++ SetMaxEpisodeSteps(0) still removes it.
  if (limit != -1 && (limit < 1 || limit > kMaxEpisodeStepsLimit)) {
    throw ConfigError("env '" + registration.id +
                      "': option 'max_episode_steps' must be -1 (the env's own limit) or in [1, " +
                      std::to_string(kMaxEpisodeStepsLimit) + "], got " + std::to_string(limit));
  }
  if (limit >= 0) env->SetMaxEpisodeSteps(limit);
  // the env's own limit (a horizon option) has the same bound: a 10^12-step episode never ends
  // in practice, and a trainer checks for signals between episodes' rounds
  const int64_t steps = env->spec().max_episode_steps;
  if (steps > kMaxEpisodeStepsLimit) {
    throw ConfigError("env '" + registration.id + "': its options make episodes of " +
                      std::to_string(steps) + " steps, more than the " +
                      std::to_string(kMaxEpisodeStepsLimit) +
                      " allowed; lower its horizon (or set max_episode_steps)");
  }
  if (const int64_t repeat = resolved.Int(kActionRepeatOption); repeat > 1) {
    env = std::make_unique<ActionRepeat>(std::move(env), repeat);
  }
  if (resolved.String(kObsOption) == "pixels") {
    if (!pixel_wrapper_) {
      throw ConfigError("env '" + registration.id +
                        "': obs=pixels needs a renderer, and this registry has none (the "
                        "default registry of a build with MuJoCo has one)");
    }
    env = pixel_wrapper_(std::move(env), PixelSettings{resolved.Int(kPixelWidthOption),
                                                       resolved.Int(kPixelHeightOption),
                                                       resolved.String(kCameraOption),
                                                       resolved.String(kPixelQualityOption) ==
                                                           "full"});
  } else if (std::any_of(registration.options.begin(), registration.options.end(),
                         [&](const OptionSpec& o) {
                           // a pixel setting away from its default, without pixels
                           return (o.name == kCameraOption || o.name == kPixelWidthOption ||
                                   o.name == kPixelHeightOption ||
                                   o.name == kPixelQualityOption) &&
                                  resolved.values()[o.name] != o.default_value;
                         })) {
    throw ConfigError("env '" + registration.id +
                      "': options camera, pixel_width, pixel_height and pixel_quality apply to "
                      "pixel observations; add obs=pixels (or leave them out)");
  }
  if (resolved.Bool(kTerminateOnSuccessOption)) {
    env = std::make_unique<TerminateOnSuccess>(std::move(env));
  }
  if (resolved.Bool(kRecurrentMetaObsOption)) {
    env = std::make_unique<RecurrentMetaObservation>(std::move(env),
                                                     resolved.Float(kRecurrentMetaObsScaleOption));
  }
  if (const int64_t frames = resolved.Int(kFrameStackOption); frames > 1) {
    env = std::make_unique<FrameStack>(std::move(env), frames);
  }
  return env;
}

}  // namespace manyworlds
