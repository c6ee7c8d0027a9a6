#pragma once
// The JSON Schema of a scheme document, written from the field table (scheme_fields.hpp).
// schema/scheme.schema.json is this document as `triax scheme-schema` prints it; the
// server test "the checked-in scheme schema is the generated one" fails when they differ.
#include <string>

#include <nlohmann/json.hpp>

namespace triax::io {

nlohmann::ordered_json scheme_schema();
// The text of schema/scheme.schema.json: scheme_schema() indented by 2, with a final newline.
std::string scheme_schema_text();

}  // namespace triax::io
