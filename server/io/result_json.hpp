#pragma once
// TestResult -> JSON in lab units with unit-suffixed names (docs/api.md): the summary of
// GET /runs/{id}/results/summary, the series (columns + rows) and the SSE event payloads.
// Soil-mechanics signs: compression and contraction positive.
#include <string>

#include <nlohmann/json.hpp>

#include "engine/protocol/test_result.hpp"

namespace triax::io {

// {"sigma3_kPa", "q_failure_kPa", "axial_strain_at_failure_pct", "particle_count", ...,
//  "consolidation": {...}, "creep_stages": [...]}
nlohmann::json result_summary_to_json(const protocol::TestResult& r);

// One series as {"series": name, "columns": [...], "rows": [[...]]}. Names:
// "stress_strain", "volumetric", "creep" (translated per stage, stage column first),
// "creep_raw", "energies", "measurements". Throws std::invalid_argument on an unknown name.
nlohmann::json result_series_to_json(const protocol::TestResult& r, const std::string& series);

// Everything: {"summary": ..., "series": {name: {...}, ...}}.
nlohmann::json result_to_json(const protocol::TestResult& r);

// SSE / observer payloads (docs/api.md event types).
nlohmann::json shear_point_to_json(const protocol::ShearPoint& p);
nlohmann::json creep_point_to_json(int stage, const protocol::CreepPoint& p);
nlohmann::json energy_sample_to_json(const protocol::EnergySample& e);
nlohmann::json measurement_sample_to_json(const protocol::MeasurementSample& m);

}  // namespace triax::io
