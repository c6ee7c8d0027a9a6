// The service validates schemes against schema/scheme.schema.json (written with the
// protocol). Every preset the service offers must pass it, and a broken preset must be
// refused with the pointer of the broken field.
#include "server/io/json_schema_validator.hpp"
#include "server/io/scheme_json.hpp"
#include "server/io/scheme_schema.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using nlohmann::json;

TEST_CASE("presets pass schema/scheme.schema.json - a broken field is named", "[server][schema]") {
    const auto path = std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "scheme.schema.json";
    if (!std::filesystem::exists(path)) {
        WARN("schema/scheme.schema.json is not in the tree yet; the service skips the JSON Schema check");
        return;
    }
    std::ifstream in(path);
    const triax::io::JsonSchemaValidator validator(json::parse(in));
    const auto presets = triax::io::presets_to_json()["presets"];
    REQUIRE_FALSE(presets.empty());
    for (const auto& p : presets) {
        const auto errors = validator.validate(p["scheme"]);
        INFO(p["name"] << ": " << (errors.empty() ? "" : errors.front().pointer + " " + errors.front().message));
        CHECK(errors.empty());
    }
    json broken = presets[0]["scheme"];
    broken["specimen"]["target_porosity"] = 1.5;
    const auto errors = validator.validate(broken);
    REQUIRE_FALSE(errors.empty());
    CHECK(errors.front().pointer == "/specimen/target_porosity");
}

// The field table (server/io/scheme_fields.cpp) is the one source of the scheme's fields:
// the checked-in schema must be what it generates. To update it after changing the table:
//   build/server/triax scheme-schema > schema/scheme.schema.json
TEST_CASE("the checked-in scheme schema is the one the field table generates", "[server][schema]") {
    const auto path = std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "scheme.schema.json";
    std::ifstream in(path);
    REQUIRE(in);
    std::stringstream text;
    text << in.rdbuf();
    const auto generated = triax::io::scheme_schema_text();
    INFO("schema/scheme.schema.json differs from `triax scheme-schema`; regenerate it");
    CHECK(json::parse(text.str()) == json::parse(generated));
    CHECK(text.str() == generated);
}

TEST_CASE("every field of the schema is read by the parser and every parsed field is in the schema", "[server][schema]") {
    // A document with every field of the normalised form passes both.
    const auto full = triax::io::scheme_to_json(triax::protocol::TestScheme{});
    const triax::io::JsonSchemaValidator validator(json::parse(triax::io::scheme_schema_text()));
    const auto errors = validator.validate(full);
    INFO((errors.empty() ? "" : errors.front().pointer + " " + errors.front().message));
    CHECK(errors.empty());
    CHECK_NOTHROW(triax::io::scheme_from_json(full));
    // And the schema names no field scheme_to_json leaves out.
    const auto schema = json::parse(triax::io::scheme_schema_text());
    for (const auto& [section, body] : schema["properties"].items()) {
        if (!body.contains("properties")) {
            if (section != "preset") CHECK(full.contains(section));
            continue;
        }
        for (const auto& [key, _] : body["properties"].items()) {
            INFO(section << "/" << key);
            CHECK(full[section].contains(key));
        }
    }
}

TEST_CASE("retired fields of stored schemes still read - new documents may not send them", "[server][schema]") {
    // One rolling setting: micro.rolling_friction. A stored document's switch on gives its
    // value as mu_r; off, micro.rolling_friction stands; the lab strain rate is ignored.
    const auto on = triax::io::scheme_from_json(json::parse(
        R"({"micro": {"rolling_friction": 0}, "effects": {"rolling_resistance": true, "rolling_friction": 0.25},
            "loading": {"shear_strain_rate_pct_per_min": 0.01}})"));
    CHECK(on.micro.rolling_friction == 0.25);
    const auto on_default = triax::io::scheme_from_json(json::parse(R"({"effects": {"rolling_resistance": true}})"));
    CHECK(on_default.micro.rolling_friction == 0.1);
    const auto off = triax::io::scheme_from_json(json::parse(
        R"({"micro": {"rolling_friction": 0.05}, "effects": {"rolling_resistance": false, "rolling_friction": 0.25}})"));
    CHECK(off.micro.rolling_friction == 0.05);
    CHECK_THROWS_AS(triax::io::scheme_from_json(json::parse(R"({"effects": {"rolling_resistance": 1}})")),
                    triax::io::SchemeError);
    // The normalised form carries only the one setting.
    const auto normalised = triax::io::scheme_to_json(on);
    CHECK(normalised["micro"]["rolling_friction"] == 0.25);
    CHECK_FALSE(normalised["effects"].contains("rolling_resistance"));
    CHECK_FALSE(normalised["effects"].contains("rolling_friction"));
    CHECK_FALSE(normalised["loading"].contains("shear_strain_rate_pct_per_min"));
    // The schema, which the service checks new documents against, has none of them.
    const triax::io::JsonSchemaValidator validator(json::parse(triax::io::scheme_schema_text()));
    const auto errors = validator.validate(json::parse(R"({"effects": {"rolling_resistance": true}})"));
    REQUIRE_FALSE(errors.empty());
    CHECK(errors.front().pointer == "/effects/rolling_resistance");
    CHECK_FALSE(validator.validate(json::parse(R"({"loading": {"shear_strain_rate_pct_per_min": 1}})")).empty());
}

TEST_CASE("a stored scheme is served without its retired fields, their meaning kept", "[server][schema]") {
    const json stored = json::parse(
        R"({"name": "old", "micro": {"friction": 0.5, "rolling_friction": 0},
            "effects": {"rolling_resistance": true, "rolling_friction": 0.25, "seating_error": false},
            "loading": {"shear_strain_rate_pct_per_min": 0.01, "confining_pressure_kPa": 100}})");
    const json served = triax::io::without_retired_fields(stored);
    CHECK(served["micro"]["rolling_friction"] == 0.25);
    CHECK(served["micro"]["friction"] == 0.5);
    CHECK(served["effects"] == json{{"seating_error", false}});
    CHECK(served["loading"] == json{{"confining_pressure_kPa", 100}});
    // The same scheme as the parser reads the stored document, and the schema accepts it.
    CHECK(triax::io::scheme_to_json(triax::io::scheme_from_json(served)) ==
          triax::io::scheme_to_json(triax::io::scheme_from_json(stored)));
    const triax::io::JsonSchemaValidator validator(json::parse(triax::io::scheme_schema_text()));
    CHECK(validator.validate(served).empty());
    // Switch off: micro.rolling_friction stands; a current document is unchanged.
    const json off = triax::io::without_retired_fields(
        json::parse(R"({"micro": {"rolling_friction": 0.05}, "effects": {"rolling_resistance": false, "rolling_friction": 0.3}})"));
    CHECK(off["micro"]["rolling_friction"] == 0.05);
    CHECK(off["effects"].empty());
    const json current = triax::io::scheme_to_json(triax::protocol::TestScheme{});
    CHECK(triax::io::without_retired_fields(current) == current);
}
