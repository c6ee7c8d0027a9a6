#include "server/io/scheme_schema.hpp"

#include "server/io/scheme_fields.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace triax::io {

using nlohmann::ordered_json;

namespace {

// A bound as the schema writes it: whole numbers as integers ("minimum": 0, not 0.0).
ordered_json number(double v) {
    if (std::floor(v) == v && std::abs(v) < 1e15) return static_cast<std::int64_t>(v);
    return v;
}

ordered_json number_schema(const NumberField& f) {
    ordered_json s{{"type", "number"}};
    if (f.bounds.min) s["minimum"] = number(*f.bounds.min);
    if (f.bounds.max) s["maximum"] = number(*f.bounds.max);
    if (f.bounds.above) s["exclusiveMinimum"] = number(*f.bounds.above);
    if (f.bounds.below) s["exclusiveMaximum"] = number(*f.bounds.below);
    if (f.description) s["description"] = f.description;
    return s;
}

ordered_json bool_schema(const BoolField& f) {
    ordered_json s{{"type", "boolean"}};
    if (f.description) s["description"] = f.description;
    return s;
}

ordered_json object_of(ordered_json properties) {
    return {{"type", "object"}, {"additionalProperties", false}, {"properties", std::move(properties)}};
}

}  // namespace

ordered_json scheme_schema() {
    ordered_json top = ordered_json::object();
    for (const auto& f : shaped_fields())
        if (std::string(f.section).empty()) top[f.key] = f.schema;
    for (const char* section : kSchemeSections) {
        ordered_json props = ordered_json::object();
        for (const auto& f : number_fields())
            if (section == std::string(f.section)) props[f.key] = number_schema(f);
        for (const auto& f : bool_fields())
            if (section == std::string(f.section)) props[f.key] = bool_schema(f);
        for (const auto& f : shaped_fields())
            if (section == std::string(f.section)) props[f.key] = f.schema;
        top[section] = object_of(std::move(props));
    }
    ordered_json schema{
        {"$schema", "https://json-schema.org/draft/2020-12/schema"},
        {"$id", "https://triax.local/schema/scheme"},
        {"title", "Triaxial + multi-stage creep test scheme"},
        {"description",
         "Lab units in every field name (mm, kPa, MPa, %, min). Every field is optional; missing fields take the seed "
         "paper's defaults (group B). Unknown fields are rejected. Generated from the field table of "
         "server/io/scheme_fields.cpp (`triax scheme-schema`); do not edit by hand."},
    };
    auto body = object_of(std::move(top));
    for (auto it = body.begin(); it != body.end(); ++it) schema[it.key()] = it.value();
    return schema;
}

std::string scheme_schema_text() { return scheme_schema().dump(2) + "\n"; }

}  // namespace triax::io
