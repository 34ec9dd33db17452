#include "manyworlds/config/override.h"

#include <charconv>
#include <optional>

#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds {
namespace {

enum class Mode { kReplace, kAdd, kAddOrReplace };

std::vector<std::string> SplitPath(std::string_view path, std::string_view text) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    const std::string_view part =
        path.substr(start, dot == std::string_view::npos ? dot : dot - start);
    if (part.empty()) {
      throw ConfigError("override '" + std::string(text) + "': the key '" +
                        ShortenForMessage(std::string(path)) +
                        "' has an empty part");
    }
    parts.emplace_back(part);
    if (dot == std::string_view::npos) return parts;
    start = dot + 1;
  }
}

std::optional<size_t> AsIndex(const std::string& part) {
  size_t index = 0;
  auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), index);
  if (ec != std::errc() || end != part.data() + part.size()) return std::nullopt;
  return index;
}

std::string Join(const std::vector<std::string>& parts, size_t count) {
  std::string out;
  for (size_t i = 0; i < count; ++i) out += (i ? "." : "") + parts[i];
  return out;
}

}  // namespace

void ApplyOverride(nlohmann::json& config, std::string_view override_text) {
  // for messages only: an override of 5,000 characters is shown cut to 80
  const std::string text = ShortenForMessage(std::string(override_text));
  std::string_view body = override_text;
  Mode mode = Mode::kReplace;
  if (body.starts_with("++")) {
    mode = Mode::kAddOrReplace;
    body.remove_prefix(2);
  } else if (body.starts_with("+")) {
    mode = Mode::kAdd;
    body.remove_prefix(1);
  }
  const size_t eq = body.find('=');
  if (eq == std::string_view::npos) {
    throw ConfigError("override '" + text + "' is not of the form key=value (e.g. seed=3)");
  }
  const std::string_view path = body.substr(0, eq);
  const std::string_view value_text = body.substr(eq + 1);
  if (path.empty()) throw ConfigError("override '" + text + "' has an empty key");
  const std::vector<std::string> parts = SplitPath(path, text);
  nlohmann::json value = value_text.empty()
                             ? nlohmann::json(std::string())
                             : ParseYaml(value_text, "override '" + text + "'");

  if (config.is_null()) config = nlohmann::json::object();
  nlohmann::json* node = &config;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    if (node->is_array()) {
      const auto index = AsIndex(part);
      if (!index || *index >= node->size()) {
        throw ConfigError("override '" + text + "': '" + Join(parts, i) + "' is a list of " +
                          std::to_string(node->size()) + " items; '" + part +
                          "' is not a valid index");
      }
      node = &(*node)[*index];
      if (last) {
        if (mode == Mode::kAdd) {
          throw ConfigError("override '" + text + "': '" + ShortenForMessage(std::string(path)) +
                            "' already exists; drop the '+' to replace it");
        }
        *node = std::move(value);
        return;
      }
      continue;
    }
    if (!node->is_object()) {
      throw ConfigError("override '" + text + "': '" + Join(parts, i) +
                        "' is a value, not a section; it has no key '" + part + "'");
    }
    auto it = node->find(part);
    if (it == node->end()) {
      if (mode == Mode::kReplace) {
        std::vector<std::string> keys;
        for (const auto& item : node->items()) keys.push_back(item.key());
        const std::string where = i == 0 ? "the config" : "'" + Join(parts, i) + "'";
        throw ConfigError("override '" + text + "': " + where + " has no key '" + part + "'" +
                          SuggestNearest(part, keys) + "; use '+" + std::string(path) +
                          "=...' to add a new key");
      }
      // '+' creates the missing sections on the way.
      it = node->emplace(part, last ? nlohmann::json() : nlohmann::json::object()).first;
    } else if (last && mode == Mode::kAdd) {
      throw ConfigError("override '" + text + "': '" + ShortenForMessage(std::string(path)) +
                        "' already exists; drop the '+' to replace it");
    }
    node = &*it;
    if (last) *node = std::move(value);
  }
}

void ApplyOverrides(nlohmann::json& config, const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) ApplyOverride(config, o);
}

}  // namespace manyworlds
