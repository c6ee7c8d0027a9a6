#pragma once
// The production RunExecutor: parses the normalised scheme (server/io/scheme_json), runs
// protocol::run_triaxial_test with an observer that streams events in lab units, and
// turns the TestResult into the stored result document (summary + series, lab units,
// compression positive).
#include "server/runs/run_executor.hpp"

#include "engine/protocol/test_result.hpp"

namespace triax::service {

RunExecutor make_engine_executor();

// TestResult -> {"summary": ..., "series": {name: rows}} in the columns of series_specs().
nlohmann::json result_document(const protocol::TestResult& r);

}  // namespace triax::service
