#pragma once
// TestResult series as CSV text: first line the column headers with units (the same names
// as the JSON series), then one row per reading.
#include <string>

#include <nlohmann/json.hpp>

#include "engine/protocol/test_result.hpp"

namespace triax::io {

// A series JSON ({"columns", "rows"}) as CSV.
std::string series_json_to_csv(const nlohmann::json& series);

// result_series_to_json(r, series) as CSV.
std::string result_series_to_csv(const protocol::TestResult& r, const std::string& series);

}  // namespace triax::io
