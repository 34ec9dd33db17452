// A metrics log kept as JSON lines plus a CSV view of the same rows.
//
// Each Append writes one JSON object as a line of NAME.jsonl (flushed at
// once) and one row of NAME.csv. Nested objects are flattened into CSV
// columns with dotted names ("per_task.reach.success"); null is an empty
// cell. CSV columns are "step" then the keys in first-seen order: when a row brings a new
// key, the CSV is rewritten from the JSON lines (atomically), so every row
// has every column.
#ifndef MANYWORLDS_EXPERIMENTS_RUN_RUN_LOG_H_
#define MANYWORLDS_EXPERIMENTS_RUN_RUN_LOG_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace manyworlds::experiments {

// Flattens nested objects into dotted keys (arrays stay values).
nlohmann::json FlattenJson(const nlohmann::json& json);

// Reads a JSON-lines file (skipping a torn last line). Throws Error naming
// the file on an unreadable line in the middle.
std::vector<nlohmann::json> ReadJsonLines(const std::filesystem::path& path);

class RunLog {
 public:
  // dir/NAME.jsonl and dir/NAME.csv. Existing rows are kept (and their keys
  // become the CSV columns).
  RunLog(const std::filesystem::path& dir, const std::string& name);

  void Append(const nlohmann::json& row);

  // Keeps only rows whose "step" is <= step (for a resumed run: rows logged
  // after its checkpoint are dropped, the run writes them again). Rewrites
  // both files atomically.
  void TruncateAfter(int64_t step);

  const std::filesystem::path& jsonl_path() const { return jsonl_; }
  const std::filesystem::path& csv_path() const { return csv_; }

 private:
  void RewriteCsv(const std::vector<nlohmann::json>& rows);
  std::string CsvRow(const nlohmann::json& flat) const;
  bool AddColumns(const nlohmann::json& flat);

  std::filesystem::path jsonl_, csv_;
  std::vector<std::string> columns_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_RUN_RUN_LOG_H_
