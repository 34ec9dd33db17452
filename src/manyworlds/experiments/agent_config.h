// The agent section of a training config: the algorithm's registry name and
// its typed config behind one small interface, so that the algorithm
// registry (algorithms.cc) is the only list of algorithms. Every config type
// lists its keys once, in VisitFields; reading, printing and validating go
// through it.
#ifndef MANYWORLDS_EXPERIMENTS_AGENT_CONFIG_H_
#define MANYWORLDS_EXPERIMENTS_AGENT_CONFIG_H_

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "manyworlds/config/reader.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds::experiments {

// One algorithm's config, type-erased.
class AgentParams {
 public:
  virtual ~AgentParams() = default;
  virtual std::unique_ptr<AgentParams> Clone() const = 0;
  // Reads every key of the config that `reader` has (unknown keys are left
  // for reader.Finish() to report).
  virtual void Read(ConfigReader& reader) = 0;
  // Every key, defaults included.
  virtual nlohmann::json ToJson() const = 0;
  // ConfigError naming the first bad field.
  virtual void Validate() const = 0;
};

namespace detail {

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

// An optional number: a number, or null for "unset" (the config's comment
// says what unset means).
template <class T>
void ReadField(ConfigReader& r, const char* key, std::optional<T>& field) {
  if (!r.Has(key)) return;
  nlohmann::json value;
  r.Read(key, value);
  if (value.is_null()) {
    field.reset();
  } else if (value.is_number()) {
    field = value.get<T>();
  } else {
    throw ConfigError("'" + r.FullKey(key) + "' must be a number or null, got " +
                      ShortenForMessage(value.dump()));
  }
}

template <class T>
void ReadField(ConfigReader& r, const char* key, T& field) {
  r.Read(key, field);
}

template <class T>
nlohmann::json FieldJson(const T& field) {
  if constexpr (IsOptional<T>::value) {
    return field ? nlohmann::json(*field) : nlohmann::json(nullptr);
  } else {
    return nlohmann::json(field);
  }
}

}  // namespace detail

// A config type C with VisitFields(f) calling f(key, field) for every key,
// and Validate().
template <class C>
class TypedAgentParams final : public AgentParams {
 public:
  TypedAgentParams() = default;
  explicit TypedAgentParams(C value) : value(std::move(value)) {}

  std::unique_ptr<AgentParams> Clone() const override {
    return std::make_unique<TypedAgentParams>(value);
  }
  void Read(ConfigReader& r) override {
    value.VisitFields([&](const char* key, auto& field) { detail::ReadField(r, key, field); });
  }
  nlohmann::json ToJson() const override {
    nlohmann::json j = nlohmann::json::object();
    C copy = value;  // VisitFields hands out mutable references
    copy.VisitFields([&](const char* key, auto& field) { j[key] = detail::FieldJson(field); });
    return j;
  }
  void Validate() const override { value.Validate(); }

  C value;
};

// agent: the algorithm's name (a registry row, algorithms.h), the device its learner runs on
// (`agent.device`, nn/device.h; the same key for every algorithm) and the algorithm's config.
// Default-constructed it is the default algorithm with its defaults.
class AgentConfig {
 public:
  AgentConfig();
  AgentConfig(std::string algo, std::unique_ptr<AgentParams> params)
      : algo_(std::move(algo)), params_(std::move(params)) {}
  AgentConfig(const AgentConfig& other)
      : algo_(other.algo_), device_(other.device_), params_(other.params_->Clone()) {}
  AgentConfig& operator=(const AgentConfig& other) {
    if (this != &other) {
      algo_ = other.algo_;
      device_ = other.device_;
      params_ = other.params_->Clone();
    }
    return *this;
  }
  AgentConfig(AgentConfig&&) = default;
  AgentConfig& operator=(AgentConfig&&) = default;

  // The registry name of the algorithm ("sac", "ppo", ...).
  const std::string& algo() const { return algo_; }
  // As written: auto, cpu, cuda or cuda:N (checked by ValidateAgentConfig, resolved when the
  // learner is built).
  const std::string& device() const { return device_; }
  void set_device(std::string device) { device_ = std::move(device); }
  AgentParams& params() { return *params_; }
  const AgentParams& params() const { return *params_; }

  // The typed config; ConfigError if the agent is another algorithm.
  template <class C>
  C& as() {
    if (auto* typed = dynamic_cast<TypedAgentParams<C>*>(params_.get())) return typed->value;
    throw ConfigError("the agent is '" + algo_ + "', not the algorithm this code expects");
  }
  template <class C>
  const C& as() const {
    return const_cast<AgentConfig*>(this)->as<C>();
  }

 private:
  std::string algo_;
  std::string device_ = "auto";
  std::unique_ptr<AgentParams> params_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_AGENT_CONFIG_H_
