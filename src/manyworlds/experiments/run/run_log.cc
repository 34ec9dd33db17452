#include "manyworlds/experiments/run/run_log.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

void FlattenInto(const nlohmann::json& json, const std::string& prefix, nlohmann::json& out) {
  for (const auto& [key, value] : json.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    if (value.is_object()) {
      FlattenInto(value, name, out);
    } else {
      out[name] = value;
    }
  }
}

std::string CsvCell(const nlohmann::json& value) {
  if (value.is_null()) return "";
  std::string text = value.is_string() ? value.get<std::string>() : value.dump();
  if (text.find_first_of(",\"\n") != std::string::npos) {
    std::string quoted = "\"";
    for (char c : text) {
      if (c == '"') quoted += '"';
      quoted += c;
    }
    return quoted + "\"";
  }
  return text;
}

std::string CsvHeaderCell(const std::string& name) { return CsvCell(nlohmann::json(name)); }

}  // namespace

nlohmann::json FlattenJson(const nlohmann::json& json) {
  nlohmann::json out = nlohmann::json::object();
  FlattenInto(json, "", out);
  return out;
}

std::vector<nlohmann::json> ReadJsonLines(const std::filesystem::path& path) {
  std::vector<nlohmann::json> rows;
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return rows;
  std::istringstream in(ReadRegularFile(path));  // a FIFO in its place is an error, not a hang
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    auto row = nlohmann::json::parse(lines[i], nullptr, false);
    if (row.is_discarded() || !row.is_object()) {
      if (i + 1 == lines.size()) break;  // torn by a crash mid-write
      throw Error(path.string() + ":" + std::to_string(i + 1) + ": not a JSON object");
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

RunLog::RunLog(const std::filesystem::path& dir, const std::string& name)
    : jsonl_(dir / (name + ".jsonl")), csv_(dir / (name + ".csv")) {
  for (const auto& row : ReadJsonLines(jsonl_)) AddColumns(FlattenJson(row));
}

bool RunLog::AddColumns(const nlohmann::json& flat) {
  bool added = false;
  for (const auto& [key, value] : flat.items()) {
    if (std::find(columns_.begin(), columns_.end(), key) == columns_.end()) {
      // objects iterate in sorted key order; "step" leads every table
      if (key == "step") {
        columns_.insert(columns_.begin(), key);
      } else {
        columns_.push_back(key);
      }
      added = true;
    }
  }
  return added;
}

std::string RunLog::CsvRow(const nlohmann::json& flat) const {
  std::string line;
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) line += ",";
    auto it = flat.find(columns_[i]);
    if (it != flat.end()) line += CsvCell(*it);
  }
  return line + "\n";
}

void RunLog::RewriteCsv(const std::vector<nlohmann::json>& rows) {
  std::string text;
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) text += ',';
    text += CsvHeaderCell(columns_[i]);
  }
  text += "\n";
  for (const auto& row : rows) text += CsvRow(FlattenJson(row));
  AtomicWriteFile(csv_, text);
}

void RunLog::Append(const nlohmann::json& row) {
  {
    std::ofstream out(jsonl_, std::ios::app);
    out << row.dump() << "\n";
    out.flush();
    if (!out) throw Error("cannot append to '" + jsonl_.string() + "'");
  }
  const nlohmann::json flat = FlattenJson(row);
  if (AddColumns(flat) || !std::filesystem::exists(csv_)) {
    RewriteCsv(ReadJsonLines(jsonl_));
    return;
  }
  std::ofstream out(csv_, std::ios::app);
  out << CsvRow(flat);
  out.flush();
  if (!out) throw Error("cannot append to '" + csv_.string() + "'");
}

void RunLog::TruncateAfter(int64_t step) {
  std::vector<nlohmann::json> kept;
  std::string text;
  for (auto& row : ReadJsonLines(jsonl_)) {
    if (row.contains("step") && row["step"].is_number() && row["step"].get<int64_t>() > step) {
      continue;
    }
    text += row.dump() + "\n";
    kept.push_back(std::move(row));
  }
  AtomicWriteFile(jsonl_, text);
  columns_.clear();
  for (const auto& row : kept) AddColumns(FlattenJson(row));
  RewriteCsv(kept);
}

}  // namespace manyworlds::experiments
