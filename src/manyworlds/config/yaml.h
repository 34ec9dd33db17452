// YAML <-> JSON. Configuration files are YAML; inside the program every
// configuration is a nlohmann::json tree.
//
// Plain scalars resolve as in the YAML 1.2 core schema: `42` is an int,
// `0.5`, `1e-3`, `.inf` are floats, `true`/`false` bools, `null`/`~`/empty
// null, anything else a string. Quoted scalars are always strings.
#ifndef MANYWORLDS_CONFIG_YAML_H_
#define MANYWORLDS_CONFIG_YAML_H_

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace manyworlds {

// Parses one YAML document. Throws ConfigError "<source>:<line>:<column>:
// <what>" on syntax errors, duplicate keys and non-scalar keys.
nlohmann::json ParseYaml(std::string_view text, std::string_view source = "<string>");

// Reads and parses a file; errors name the file and the line.
nlohmann::json LoadYamlFile(const std::filesystem::path& path);

// Block-style YAML that ParseYaml reads back to an equal tree: ints stay ints,
// floats keep a decimal point or exponent, strings that would read as
// another type are quoted. Ends with a newline.
std::string DumpYaml(const nlohmann::json& json);

}  // namespace manyworlds

#endif  // MANYWORLDS_CONFIG_YAML_H_
