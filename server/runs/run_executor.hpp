#pragma once
// What a run job needs from the thing that actually simulates: the service hands it the
// normalised scheme (lab-unit JSON), a thread count, a cancel flag and an event sink, and
// gets back the result document in lab units:
//   {"summary": {...}, "series": {"stress_strain": {"columns": [...], "rows": [[...]]},
//    "volumetric": ..., "creep": ..., "energies": ..., "measurements": ...}}
// The production executor runs the engine (engine_executor.hpp); tests of the service's
// own mechanics (queue, cancel, replay, restart) may pass another.
#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace triax::service {

struct RunContext {
    std::int64_t run_id = 0;
    int threads = 1;
    std::function<bool()> cancel_requested;
    // Streams one event (types and fields of docs/api.md, lab units); cheap to call.
    std::function<void(const std::string& type, const nlohmann::json& data)> emit;
    // Keeps the specimen at the end of a stage: its counts ({"stage", "grains",
    // "membrane_particles", "contacts"}) and its stored form (io::encode_snapshot).
    std::function<void(const nlohmann::json& counts, const std::string& bytes)> store_snapshot;
    // The packing the run starts from (project JSON, SI; docs/packings.md), null when the
    // specimen is generated.
    nlohmann::json packing;
};

// Thrown by an executor that stopped because cancel_requested() became true.
struct RunCancelled : std::runtime_error {
    RunCancelled() : std::runtime_error("run cancelled") {}
};

using RunExecutor = std::function<nlohmann::json(const nlohmann::json& scheme, RunContext& ctx)>;

// Columns of each stored series (docs/api.md "Results"), shared by the executor, the
// event-derived partial series and the OpenAPI description.
struct SeriesSpec {
    const char* name;        // stress_strain, volumetric, creep, energies, measurements
    const char* event_type;  // the event whose data rows make the partial series
    std::vector<std::string> columns;
};
const std::vector<SeriesSpec>& series_specs();
const SeriesSpec* find_series(const std::string& name);

}  // namespace triax::service
