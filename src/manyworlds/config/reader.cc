#include "manyworlds/config/reader.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds {
namespace {

const nlohmann::json& EmptyObject() {
  static const nlohmann::json empty = nlohmann::json::object();
  return empty;
}

std::string Describe(const nlohmann::json& value) {
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {  // JSON writes null
    const double x = value.get<double>();
    return std::string(std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf") + " (number)";
  }
  std::string shown = value.dump();
  if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
  return shown + " (" + value.type_name() + ")";
}

}  // namespace

ConfigReader::ConfigReader(const nlohmann::json& json, std::string path)
    : json_(json.is_null() ? EmptyObject() : json), path_(std::move(path)) {
  if (!json_.is_object()) {
    throw ConfigError((path_.empty() ? std::string("the config") : "config key '" + path_ + "'") +
                      " must be a map of keys to values, got " + Describe(json_));
  }
}

std::string ConfigReader::FullKey(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

bool ConfigReader::Has(std::string_view key) const { return json_.contains(key); }

const nlohmann::json* ConfigReader::Find(std::string_view key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
  auto it = json_.find(key);
  return it == json_.end() ? nullptr : &*it;
}

void ConfigReader::TypeError(std::string_view key, const nlohmann::json& value,
                             std::string_view expected) const {
  throw ConfigError("config key '" + FullKey(key) + "' must be " + std::string(expected) +
                    ", got " + Describe(value));
}

int64_t ConfigReader::ReadInteger(std::string_view key, const nlohmann::json& value, int64_t low,
                                  int64_t high, std::string_view expected) const {
  if (value.is_number_unsigned()) {
    const uint64_t u = value.get<uint64_t>();
    if (u > static_cast<uint64_t>(high)) TypeError(key, value, expected);
    return static_cast<int64_t>(u);
  }
  if (!value.is_number_integer()) TypeError(key, value, expected);
  const int64_t v = value.get<int64_t>();
  if (v < low || v > high) TypeError(key, value, expected);
  return v;
}

void ConfigReader::Read(std::string_view key, bool& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_boolean()) TypeError(key, *v, "a bool (true or false)");
    value = v->get<bool>();
  }
}

void ConfigReader::Read(std::string_view key, int& value) {
  if (const auto* v = Find(key)) {
    value = static_cast<int>(ReadInteger(key, *v, std::numeric_limits<int>::min(),
                                         std::numeric_limits<int>::max(), "an int"));
  }
}

void ConfigReader::Read(std::string_view key, int64_t& value) {
  if (const auto* v = Find(key)) {
    value = ReadInteger(key, *v, std::numeric_limits<int64_t>::min(),
                        std::numeric_limits<int64_t>::max(), "an int");
  }
}

void ConfigReader::Read(std::string_view key, uint64_t& value) {
  if (const auto* v = Find(key)) {
    if (v->is_number_unsigned()) {
      value = v->get<uint64_t>();
    } else {
      value = static_cast<uint64_t>(ReadInteger(key, *v, 0, std::numeric_limits<int64_t>::max(),
                                                "a non-negative int"));
    }
  }
}

void ConfigReader::Read(std::string_view key, double& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_number()) TypeError(key, *v, "a number");
    value = v->get<double>();
  }
}

void ConfigReader::Read(std::string_view key, float& value) {
  double d = value;
  Read(key, d);
  value = static_cast<float>(d);
}

// Config strings (names, paths) are short: a longer one is refused before anything echoes it.
constexpr size_t kMaxStringChars = 4096;

void ConfigReader::Read(std::string_view key, std::string& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_string() || v->get_ref<const std::string&>().size() > kMaxStringChars) {
      TypeError(key, *v, "a string of at most " + std::to_string(kMaxStringChars) + " characters");
    }
    value = v->get<std::string>();
  }
}

void ConfigReader::Read(std::string_view key, std::vector<std::string>& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_array()) TypeError(key, *v, "a list of strings");
    std::vector<std::string> out;
    for (const auto& item : *v) {
      if (!item.is_string() || item.get_ref<const std::string&>().size() > kMaxStringChars) {
        TypeError(key, *v, "a list of strings of at most " + std::to_string(kMaxStringChars) +
                               " characters");
      }
      out.push_back(item.get<std::string>());
    }
    value = std::move(out);
  }
}

void ConfigReader::Read(std::string_view key, std::vector<int64_t>& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_array()) TypeError(key, *v, "a list of ints");
    std::vector<int64_t> out;
    for (const auto& item : *v) {
      if (!item.is_number_integer()) TypeError(key, *v, "a list of ints");
      out.push_back(item.get<int64_t>());
    }
    value = std::move(out);
  }
}

void ConfigReader::Read(std::string_view key, std::vector<double>& value) {
  if (const auto* v = Find(key)) {
    if (!v->is_array()) TypeError(key, *v, "a list of numbers");
    std::vector<double> out;
    for (const auto& item : *v) {
      if (!item.is_number()) TypeError(key, *v, "a list of numbers");
      out.push_back(item.get<double>());
    }
    value = std::move(out);
  }
}

void ConfigReader::Read(std::string_view key, nlohmann::json& value) {
  if (const auto* v = Find(key)) value = *v;
}

ConfigReader ConfigReader::Section(std::string_view key) {
  const auto* v = Find(key);
  return ConfigReader(v ? *v : EmptyObject(), FullKey(key));
}

void ConfigReader::Finish() const {
  std::string message;
  for (const auto& item : json_.items()) {
    if (std::find(known_.begin(), known_.end(), item.key()) != known_.end()) continue;
    message += (message.empty() ? "" : "; ") + std::string("unknown key '") + FullKey(item.key()) +
               "'" + SuggestNearest(item.key(), known_);
  }
  if (!message.empty()) throw ConfigError(message);
}

}  // namespace manyworlds
