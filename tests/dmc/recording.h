// The dm_control recordings of tests/dmc/data (made by scripts/record_dmc_*.py), read by the
// agreement tests. ctest sets MANYWORLDS_SOURCE_DIR.
#ifndef MANYWORLDS_TESTS_DMC_RECORDING_H_
#define MANYWORLDS_TESTS_DMC_RECORDING_H_

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace manyworlds::dmc {

// tests/dmc/data/<file> parsed; a failed expectation and null if it cannot be read.
inline nlohmann::json LoadRecording(const std::string& file) {
  const char* source = std::getenv("MANYWORLDS_SOURCE_DIR");
  EXPECT_NE(source, nullptr) << "MANYWORLDS_SOURCE_DIR is set by ctest";
  if (source == nullptr) return {};
  std::ifstream in(std::string(source) + "/tests/dmc/data/" + file);
  EXPECT_TRUE(in.good()) << "tests/dmc/data/" << file << " is missing";
  if (!in.good()) return {};
  return nlohmann::json::parse(in);
}

}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_TESTS_DMC_RECORDING_H_
