// ConfigReader binds a JSON object (usually read from YAML) to a plain
// struct whose members carry the defaults. Keys that are absent keep the
// default; keys that nobody read are errors, so a typo never goes unnoticed:
//
//   RolloutConfig cfg;                     // defaults
//   ConfigReader r(json, "rollout");
//   r.Read("episodes", cfg.episodes);
//   r.Read("seed", cfg.seed);
//   r.Finish();   // ConfigError: unknown key 'rollout.episdoes'
//                 //   (did you mean 'episodes'?)
//
// Type errors name the full key and the expected type. Integers are not
// silently truncated: 2.5 is not an int, -1 is not an unsigned.
#ifndef MANYWORLDS_CONFIG_READER_H_
#define MANYWORLDS_CONFIG_READER_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace manyworlds {

class ConfigReader {
 public:
  // `json` must be an object or null (an empty section); it must outlive the
  // reader. `path` prefixes every key in messages ("" for the root).
  explicit ConfigReader(const nlohmann::json& json, std::string path = "");

  bool Has(std::string_view key) const;

  // Each Read leaves `value` unchanged if the key is absent and records the
  // key as known (for suggestions) either way.
  void Read(std::string_view key, bool& value);
  void Read(std::string_view key, int& value);
  void Read(std::string_view key, int64_t& value);
  void Read(std::string_view key, uint64_t& value);
  void Read(std::string_view key, float& value);
  void Read(std::string_view key, double& value);
  void Read(std::string_view key, std::string& value);
  void Read(std::string_view key, std::vector<std::string>& value);
  void Read(std::string_view key, std::vector<int64_t>& value);
  void Read(std::string_view key, std::vector<double>& value);
  // Any JSON value, unchecked (for free-form sections such as env options).
  void Read(std::string_view key, nlohmann::json& value);

  // A reader for a nested section (an empty one if the key is absent).
  // Call Finish on it too.
  ConfigReader Section(std::string_view key);

  // Throws ConfigError listing every key that was present but never read.
  void Finish() const;

  // "rollout.episodes" for key "episodes".
  std::string FullKey(std::string_view key) const;

 private:
  // The value of a present key (marking it known), or nullptr.
  const nlohmann::json* Find(std::string_view key);
  [[noreturn]] void TypeError(std::string_view key, const nlohmann::json& value,
                              std::string_view expected) const;
  int64_t ReadInteger(std::string_view key, const nlohmann::json& value, int64_t low,
                      int64_t high, std::string_view expected) const;

  const nlohmann::json& json_;
  std::string path_;
  std::vector<std::string> known_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CONFIG_READER_H_
