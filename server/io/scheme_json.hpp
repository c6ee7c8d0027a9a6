#pragma once
// TestScheme <-> JSON in lab units (docs/api.md, schema/scheme.schema.json).
// Every field carries its unit in its name: specimen.diameter_mm, loading.confining_pressure_kPa,
// loading.stage_durations_min, ... Every field is optional; a missing one keeps the
// paper's default (Tables 1-3), so {} is group B. Unknown fields are rejected (a typo
// would otherwise silently run the default). The fields are the table of scheme_fields.hpp;
// its retired fields are still read from stored documents but are not in the schema, so
// the service refuses them in new ones.
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::io {

// A scheme field at fault: `field` is the JSON pointer ("/specimen/target_porosity").
struct SchemeError : std::invalid_argument {
    std::string field;
    SchemeError(std::string pointer, const std::string& detail)
        : std::invalid_argument(pointer + ": " + detail), field(std::move(pointer)) {}
};

// Parses and validates (TestScheme::validate). Throws SchemeError naming the pointer.
protocol::TestScheme scheme_from_json(const nlohmann::json& j);

// A stored document as it is served: its retired fields (scheme_fields.hpp) read into the
// current ones (the rolling switch on: its value as micro.rolling_friction) and removed, the
// rest untouched, so that a client can send it back as a new document.
nlohmann::json without_retired_fields(nlohmann::json j);

// The normalised scheme: every field present, lab units.
nlohmann::json scheme_to_json(const protocol::TestScheme& s);

// {"presets":[{"name":"B","description":"...","scheme":{...}}, ...]} (GET /presets).
nlohmann::json presets_to_json();

}  // namespace triax::io
