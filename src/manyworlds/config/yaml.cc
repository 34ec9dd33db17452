#include "manyworlds/config/yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::string Where(std::string_view source, const YAML::Mark& mark) {
  std::string out(source);
  if (!mark.is_null()) {
    out += ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
  }
  return out;
}

[[noreturn]] void Fail(std::string_view source, const YAML::Mark& mark, const std::string& what) {
  throw ConfigError(Where(source, mark) + ": " + what);
}

// yaml-cpp leaves typing to the caller; these follow the YAML 1.2 core schema.
bool IsNull(const std::string& s) {
  return s.empty() || s == "~" || s == "null" || s == "Null" || s == "NULL";
}

std::optional<bool> AsBool(const std::string& s) {
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  return std::nullopt;
}

// Bounds on what a config may hold: std::regex recurses per character and
// the conversion per nesting level, so unbounded input could exhaust the
// stack; aliases are shared in yaml-cpp's tree but expanded here, so a
// "billion laughs" document could exhaust memory.
constexpr size_t kMaxNumberChars = 400;  // longer plain scalars are strings
constexpr int kMaxDepth = 64;
constexpr size_t kMaxKeyChars = 256;
constexpr int64_t kMaxNodes = 1000000;

// A scalar cut for an error message.
std::string Shown(const std::string& s) {
  return s.size() <= 40 ? s : s.substr(0, 20) + "..." + s.substr(s.size() - 10) + " (" +
                                  std::to_string(s.size()) + " characters)";
}

bool AllIn(std::string_view s, bool (*digit)(char)) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!digit(c)) return false;
  }
  return true;
}
bool IsDec(char c) { return c >= '0' && c <= '9'; }
bool IsHex(char c) { return IsDec(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }
bool IsOct(char c) { return c >= '0' && c <= '7'; }

// [-+]?[0-9]+ | 0x[0-9a-fA-F]+ | 0o[0-7]+, without a regular expression
// (any length).
bool LooksLikeInt(const std::string& s) {
  std::string_view v = s;
  if (v.starts_with("0x")) return AllIn(v.substr(2), IsHex);
  if (v.starts_with("0o")) return AllIn(v.substr(2), IsOct);
  if (!v.empty() && (v.front() == '-' || v.front() == '+')) v.remove_prefix(1);
  return AllIn(v, IsDec);
}

// The first byte where `text` is not well-formed UTF-8, or npos.
size_t InvalidUtf8(std::string_view text) {
  size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    size_t extra = 0;
    uint32_t code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      code = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      code = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      code = c & 0x07;
    } else {
      return i;
    }
    if (i + extra >= text.size()) return i;  // truncated sequence
    for (size_t k = 1; k <= extra; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xC0) != 0x80) return i;
      code = (code << 6) | (next & 0x3F);
    }
    // overlong forms, surrogates and code points past U+10FFFF
    static constexpr uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (code < kMin[extra] || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF) return i;
    i += extra + 1;
  }
  return std::string_view::npos;
}

std::optional<int64_t> AsInt(const std::string& s) {
  if (!LooksLikeInt(s)) return std::nullopt;
  int base = 10;
  std::string_view digits = s;
  if (digits.starts_with("0x")) {
    base = 16;
    digits.remove_prefix(2);
  } else if (digits.starts_with("0o")) {
    base = 8;
    digits.remove_prefix(2);
  }
  if (digits.front() == '+') digits.remove_prefix(1);
  int64_t value = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value, base);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return value;
}

std::optional<double> AsFloat(const std::string& s) {
  static const std::regex kFloat("[-+]?(\\.[0-9]+|[0-9]+(\\.[0-9]*)?)([eE][-+]?[0-9]+)?");
  static const std::regex kInf("[-+]?\\.(inf|Inf|INF)");
  static const std::regex kNan("\\.(nan|NaN|NAN)");
  if (s.size() > kMaxNumberChars) return std::nullopt;
  if (std::regex_match(s, kInf)) {
    return s[0] == '-' ? -std::numeric_limits<double>::infinity()
                       : std::numeric_limits<double>::infinity();
  }
  if (std::regex_match(s, kNan)) return std::numeric_limits<double>::quiet_NaN();
  if (!std::regex_match(s, kFloat)) return std::nullopt;
  std::string_view text = s;
  if (text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// The JSON value a plain (unquoted, untagged) scalar stands for.
nlohmann::json ResolvePlain(const std::string& s) {
  if (IsNull(s)) return nullptr;
  if (auto b = AsBool(s)) return *b;
  if (auto i = AsInt(s)) return *i;
  if (LooksLikeInt(s)) return s;  // out of range; ConvertScalar reports it
  if (auto f = AsFloat(s)) return *f;
  return s;
}

nlohmann::json ConvertScalar(const YAML::Node& node, std::string_view source) {
  const std::string& text = node.Scalar();
  const std::string& tag = node.Tag();
  if (tag == "!" || tag == "tag:yaml.org,2002:str") return text;
  if (tag == "?" || tag.empty()) {
    // Integers out of range still look like integers: refuse rather than
    // silently turning them into strings.
    nlohmann::json value = ResolvePlain(text);
    if (value.is_string() && LooksLikeInt(text)) {
      Fail(source, node.Mark(), "integer '" + Shown(text) + "' is out of range");
    }
    return value;
  }
  nlohmann::json value = ResolvePlain(text);
  const bool ok = (tag == "tag:yaml.org,2002:int" && value.is_number_integer()) ||
                  (tag == "tag:yaml.org,2002:float" && value.is_number()) ||
                  (tag == "tag:yaml.org,2002:bool" && value.is_boolean()) ||
                  (tag == "tag:yaml.org,2002:null" && value.is_null());
  if (!ok) Fail(source, node.Mark(), "cannot read '" + Shown(text) + "' as " + tag);
  if (tag == "tag:yaml.org,2002:float") return value.get<double>();
  return value;
}

// `nodes` counts every node converted so far (aliases count each time they
// are expanded).
nlohmann::json Convert(const YAML::Node& node, std::string_view source, int depth,
                       int64_t& nodes) {
  if (depth > kMaxDepth) {
    Fail(source, node.Mark(),
         "nested deeper than " + std::to_string(kMaxDepth) +
             " levels (a config is a few levels deep; is an alias referring to itself?)");
  }
  if (++nodes > kMaxNodes) {
    Fail(source, node.Mark(),
         "expands to more than " + std::to_string(kMaxNodes) +
             " values (aliases are expanded; is this an alias bomb?)");
  }
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return nullptr;
    case YAML::NodeType::Scalar:
      return ConvertScalar(node, source);
    case YAML::NodeType::Sequence: {
      nlohmann::json array = nlohmann::json::array();
      for (const auto& item : node) array.push_back(Convert(item, source, depth + 1, nodes));
      return array;
    }
    case YAML::NodeType::Map: {
      nlohmann::json object = nlohmann::json::object();
      for (const auto& entry : node) {
        if (!entry.first.IsScalar()) Fail(source, entry.first.Mark(), "map keys must be scalars");
        const std::string& key = entry.first.Scalar();
        // YAML's implicit keys end at 1024 characters, so a longer one could
        // not be written back; no config needs a key anywhere near that long
        if (key.size() > kMaxKeyChars) {
          Fail(source, entry.first.Mark(),
               "key '" + Shown(key) + "' is longer than " + std::to_string(kMaxKeyChars) +
                   " characters");
        }
        // control characters are written back escaped (\u0002: six characters
        // each), which could push a key past that limit; no key needs one
        if (std::any_of(key.begin(), key.end(),
                        [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) {
          Fail(source, entry.first.Mark(), "key '" + Shown(key) + "' contains a control character");
        }
        if (object.contains(key)) {
          Fail(source, entry.first.Mark(), "duplicate key '" + Shown(key) + "'");
        }
        object[key] = Convert(entry.second, source, depth + 1, nodes);
      }
      return object;
    }
  }
  return nullptr;
}

// Strings that can be written unquoted in block and flow context alike.
bool IsSafePlain(const std::string& s) {
  if (s.size() > kMaxNumberChars) return false;  // quoted: no regex over long strings
  static const std::regex kPlain("[A-Za-z0-9_/.][A-Za-z0-9_./+-]*( [A-Za-z0-9_./+-]+)*");
  if (!std::regex_match(s, kPlain) || LooksLikeInt(s)) return false;
  const nlohmann::json resolved = ResolvePlain(s);
  return resolved.is_string();
}

std::string Scalar(const nlohmann::json& v) {
  if (v.is_object()) return "{}";
  if (v.is_array()) return "[]";
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isnan(d)) return ".nan";
    if (std::isinf(d)) return d > 0 ? ".inf" : "-.inf";
    return v.dump();  // nlohmann keeps a ".0" or an exponent: reads back as a float
  }
  if (v.is_string()) {
    const auto& s = v.get_ref<const std::string&>();
    return IsSafePlain(s) ? s : v.dump();  // a JSON string is a valid double-quoted YAML scalar
  }
  return v.dump();  // null, bool, integers
}

bool IsCollection(const nlohmann::json& v) { return (v.is_object() || v.is_array()) && !v.empty(); }

bool AllScalars(const nlohmann::json& array) {
  for (const auto& item : array) {
    if (IsCollection(item)) return false;
  }
  return true;
}

std::string FlowSequence(const nlohmann::json& array) {
  std::string out = "[";
  for (const auto& item : array) out += (out.size() > 1 ? ", " : "") + Scalar(item);
  return out + "]";
}

void EmitSequence(const nlohmann::json& array, int indent, std::string& out);

void EmitMap(const nlohmann::json& object, int indent, std::string& out) {
  const std::string pad(indent, ' ');
  for (const auto& [key, value] : object.items()) {
    out += pad + Scalar(nlohmann::json(key)) + ":";
    if (value.is_object() && !value.empty()) {
      out += "\n";
      EmitMap(value, indent + 2, out);
    } else if (value.is_array() && !value.empty() && !AllScalars(value)) {
      out += "\n";
      EmitSequence(value, indent + 2, out);
    } else if (value.is_array() && !value.empty()) {
      out += " " + FlowSequence(value) + "\n";
    } else {
      out += " " + Scalar(value) + "\n";
    }
  }
}

void EmitSequence(const nlohmann::json& array, int indent, std::string& out) {
  const std::string pad(indent, ' ');
  for (const auto& item : array) {
    out += pad + "-";
    if (item.is_object() && !item.empty()) {
      // the first key goes on the dash's line
      std::string nested;
      EmitMap(item, indent + 2, nested);
      out += " " + nested.substr(indent + 2);
    } else if (item.is_array() && !item.empty() && !AllScalars(item)) {
      out += "\n";
      EmitSequence(item, indent + 2, out);
    } else if (item.is_array() && !item.empty()) {
      out += " " + FlowSequence(item) + "\n";
    } else {
      out += " " + Scalar(item) + "\n";
    }
  }
}

}  // namespace

nlohmann::json ParseYaml(std::string_view text, std::string_view source) {
  if (const size_t bad = InvalidUtf8(text); bad != std::string_view::npos) {
    throw ConfigError(std::string(source) + ": not valid UTF-8 (byte " + std::to_string(bad) +
                      "); configs must be UTF-8 text");
  }
  // a NUL is never part of a text config, and yaml-cpp takes NULs near the
  // start as a sign of UTF-16 or UTF-32 and decodes the bytes as such
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos) {
    throw ConfigError(std::string(source) + ": contains a NUL byte (byte " + std::to_string(nul) +
                      "); configs must be UTF-8 text");
  }
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    Fail(source, e.mark, e.msg);
  }
  int64_t nodes = 0;
  return Convert(root, source, 0, nodes);
}

nlohmann::json LoadYamlFile(const std::filesystem::path& path) {
  std::string text;
  try {
    text = ReadRegularFile(path, std::uintmax_t{64} << 20);  // a pipe or device never blocks
  } catch (const Error& e) {
    throw ConfigError(std::string("config file: ") + e.what());
  }
  return ParseYaml(text, path.string());
}

std::string DumpYaml(const nlohmann::json& json) {
  std::string out;
  if (json.is_object() && !json.empty()) {
    EmitMap(json, 0, out);
  } else if (json.is_array() && !json.empty()) {
    EmitSequence(json, 0, out);
  } else {
    out = Scalar(json) + "\n";
  }
  return out;
}

}  // namespace manyworlds
