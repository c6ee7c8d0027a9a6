#pragma once
// The fields of a scheme document, one table: where each lives in the JSON (lab units),
// where it lands in TestScheme (SI), and what the JSON Schema says of it (bounds, text).
// The parser (scheme_json.cpp) reads the document through these tables and the schema
// (scheme_schema.cpp, checked in as schema/scheme.schema.json) is written from them, so a
// field exists in both or in neither.
#include <functional>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/protocol/test_scheme.hpp"

namespace triax::io {

// JSON Schema bounds of a number, in lab units: min/max inclusive, above/below exclusive.
struct Bounds {
    std::optional<double> min{}, max{}, above{}, below{};
};

// A number: JSON /section/key in lab units, TestScheme field `si_name` (the name
// TestScheme::validate uses in its messages), lab -> SI factor `to_si`.
struct NumberField {
    const char* section;
    const char* key;
    const char* si_name;
    std::function<double&(protocol::TestScheme&)> ref;
    double to_si;
    Bounds bounds;
    const char* description;  // nullptr: none
};

struct BoolField {
    const char* section;
    const char* key;
    std::function<bool&(protocol::TestScheme&)> ref;
    const char* description;  // nullptr: none
};

// A field the parser reads by hand (strings, enums, arrays; section "" = the top level),
// with its JSON Schema.
struct ShapedField {
    const char* section;
    const char* key;
    nlohmann::ordered_json schema;
};

// A field older documents carry and the parser still reads (stored schemes, diagnosis
// requests), not part of the schema: new documents may not send it.
struct RetiredField {
    const char* section;
    const char* key;
};

inline constexpr const char* kSchemeSections[] = {"specimen", "gradation", "micro", "creep", "loading", "effects"};

const std::vector<NumberField>& number_fields();
const std::vector<BoolField>& bool_fields();
const std::vector<ShapedField>& shaped_fields();
const std::vector<RetiredField>& retired_fields();

}  // namespace triax::io
