// The schema validator on the keywords schema/scheme.schema.json uses; every error must
// carry the JSON pointer of the offending value.
#include "server/io/json_schema_validator.hpp"

#include <catch2/catch.hpp>

using nlohmann::json;
using triax::io::JsonSchemaValidator;

namespace {
const json kSchema = json::parse(R"({
  "type": "object",
  "additionalProperties": false,
  "required": ["specimen"],
  "definitions": {"positive": {"type": "number", "exclusiveMinimum": 0}},
  "properties": {
    "name": {"type": "string", "maxLength": 8},
    "specimen": {
      "type": "object",
      "properties": {
        "target_porosity": {"type": "number", "exclusiveMinimum": 0, "exclusiveMaximum": 1},
        "diameter_mm": {"$ref": "#/definitions/positive"},
        "count": {"type": "integer", "minimum": 1, "maximum": 100}
      }
    },
    "levels": {"type": "array", "minItems": 1, "maxItems": 3, "items": {"type": "number", "minimum": 0, "maximum": 1}},
    "kind": {"enum": ["radius_ratio", "sieve_curve"]},
    "gradation": {"oneOf": [
       {"type": "object", "required": ["r_min_mm"], "properties": {"r_min_mm": {"type": "number"}}, "additionalProperties": false},
       {"type": "object", "required": ["sieve"], "properties": {"sieve": {"type": "array"}}, "additionalProperties": false}]}
  }
})");

std::vector<std::string> pointers(const json& doc) {
    std::vector<std::string> out;
    for (const auto& v : JsonSchemaValidator(kSchema).validate(doc)) out.push_back(v.pointer);
    return out;
}
}  // namespace

TEST_CASE("a valid document has no violation", "[server][schema]") {
    CHECK(pointers(json::parse(R"({"name":"B","specimen":{"target_porosity":0.35,"diameter_mm":100,"count":3},
        "levels":[0.1,0.4],"kind":"sieve_curve","gradation":{"r_min_mm":0.5}})"))
              .empty());
}

TEST_CASE("range violations name the field pointer and the bound", "[server][schema]") {
    const auto v = JsonSchemaValidator(kSchema).validate(json::parse(R"({"specimen":{"target_porosity":1.0}})"));
    REQUIRE(v.size() == 1);
    CHECK(v[0].pointer == "/specimen/target_porosity");
    CHECK_THAT(v[0].message, Catch::Contains("< 1"));
    CHECK(pointers(json::parse(R"({"specimen":{"target_porosity":0}})")) == std::vector<std::string>{"/specimen/target_porosity"});
    CHECK(pointers(json::parse(R"({"specimen":{"diameter_mm":-5}})")) == std::vector<std::string>{"/specimen/diameter_mm"});
    CHECK(pointers(json::parse(R"({"specimen":{"count":1e9}})")) == std::vector<std::string>{"/specimen/count"});
    CHECK(pointers(json::parse(R"({"specimen":{"count":2.5}})")) == std::vector<std::string>{"/specimen/count"});
}

TEST_CASE("types, required, unknown fields, enum, arrays and oneOf", "[server][schema]") {
    CHECK(pointers(json::parse(R"({})")) == std::vector<std::string>{"/specimen"});
    CHECK(pointers(json::parse(R"({"specimen":{},"speciman":{}})")) == std::vector<std::string>{"/speciman"});
    CHECK(pointers(json::parse(R"({"specimen":"x"})")) == std::vector<std::string>{"/specimen"});
    CHECK(pointers(json::parse(R"({"specimen":{},"kind":"other"})")) == std::vector<std::string>{"/kind"});
    CHECK(pointers(json::parse(R"({"specimen":{},"levels":[]})")) == std::vector<std::string>{"/levels"});
    CHECK(pointers(json::parse(R"({"specimen":{},"levels":[0.1,0.2,0.3,0.4]})")) == std::vector<std::string>{"/levels"});
    CHECK(pointers(json::parse(R"({"specimen":{},"levels":[0.1,1.5]})")) == std::vector<std::string>{"/levels/1"});
    CHECK(pointers(json::parse(R"({"specimen":{},"name":"much too long"})")) == std::vector<std::string>{"/name"});
    CHECK(pointers(json::parse(R"({"specimen":{},"gradation":{"sieve":[]}})")).empty());
    CHECK(pointers(json::parse(R"({"specimen":{},"gradation":{"r_min_mm":"a"}})")) ==
          std::vector<std::string>{"/gradation/r_min_mm"});
}

TEST_CASE("draft-4 boolean exclusive bounds and pointer escaping", "[server][schema]") {
    const json s = json::parse(R"({"properties":{"a/b":{"type":"number","minimum":0,"exclusiveMinimum":true}}})");
    const auto v = JsonSchemaValidator(s).validate(json::parse(R"({"a/b":0})"));
    REQUIRE(v.size() == 1);
    CHECK(v[0].pointer == "/a~1b");
    CHECK(JsonSchemaValidator(s).validate(json::parse(R"({"a/b":0.1})")).empty());
}
