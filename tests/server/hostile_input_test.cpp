// Hostile request bodies: deep nesting, duplicate keys, overflowing numbers, unbounded
// strings and wrong types must each be answered 400/422 naming the field, never end the
// process or be stored.
#include "server/io/bounded_json.hpp"
#include "service_fixture.hpp"

#include <climits>

using namespace triax::test;

namespace {
// {"name": [[[[...]]]]} nested `levels` deep, as in the report that crashed the service.
std::string deep_body(int levels) {
    return "{\"name\": " + std::string(static_cast<std::size_t>(levels), '[') + std::string(static_cast<std::size_t>(levels), ']') + "}";
}
const std::string kCsv = "confining_kPa,axial_strain_pct,q_kPa\n100,0.5,80\n100,1,120\n";
}  // namespace

TEST_CASE("parse_bounded_json refuses depth, duplicate keys, long strings and long arrays by pointer", "[server][hostile]") {
    using triax::io::JsonLimitError;
    using triax::io::JsonLimits;
    using triax::io::parse_bounded_json;
    auto refused = [](const std::string& text, const JsonLimits& l = {}) -> std::string {
        try {
            parse_bounded_json(text, l);
        } catch (const JsonLimitError& e) {
            return e.pointer + " | " + e.what();
        }
        return "accepted";
    };
    CHECK(refused(deep_body(52000)).rfind("/name/0/0", 0) == 0);
    CHECK(refused(deep_body(31)) == "accepted");  // 32 levels with the outer object
    CHECK(refused(deep_body(32)).find("nesting deeper than 32") != std::string::npos);
    CHECK(refused(R"({"a": {"b": 1, "b": 2}})") == "/a/b | duplicate key");
    CHECK(refused(R"({"a~/b": 1, "a~/b": 2})") == "/a~0~1b | duplicate key");
    JsonLimits small;
    small.max_string_bytes = 4;
    small.max_elements = 3;
    CHECK(refused(R"({"k": ["abcd", "abcde"]})", small).rfind("/k/1 | string longer", 0) == 0);
    CHECK(refused(R"({"k": [1, 2, 3, [4]]})", small).rfind("/k/3 | array with more than 3", 0) == 0);
    CHECK(refused(R"([1, 2, 3])", small) == "accepted");
    CHECK(refused("{\"a\": 1,}").find("not valid JSON") != std::string::npos);
}

TEST_CASE("52,000 levels of nested JSON on every JSON route are 422, the service keeps serving", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto ds = srv.post("/datasets?format=csv", kCsv, "text/csv");
    REQUIRE(ds.status == 201);
    const std::string diagnose = "/datasets/" + std::to_string(ds.body["id"].get<long long>()) + "/diagnose";
    for (const std::string& path : std::vector<std::string>{"/schemes", "/runs", "/comparisons", diagnose}) {
        INFO(path);
        const auto r = srv.post(path, deep_body(52000));
        check_problem(r, 422);
        CHECK(r.body.value("field", "").rfind("/name/0/0/0", 0) == 0);
        CHECK(r.text.size() < 4096);  // the bad value is not quoted back
    }
    // A JSON dataset upload is refused the same way.
    const auto up = srv.post("/datasets?format=json", deep_body(52000), "application/json");
    check_problem(up, 422);
    CHECK(srv.get("/health").status == 200);
}

TEST_CASE("duplicate keys, non-finite SI values, 2^63 threads and long names are refused by field", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    auto r = srv.post("/schemes", std::string(R"({"seed": 1, "seed": 2})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/seed");
    r = srv.post("/schemes", json{{"micro", {{"normal_modulus_MPa", 1e308}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/micro/normal_modulus_MPa");
    r = srv.post("/schemes", json{{"loading", {{"stress_levels", {0.5}}, {"stage_durations_min", {1e308}}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/loading/stage_durations_min/0");
    r = srv.post("/schemes", json{{"loading", {{"stress_levels", {0.5}}, {"stage_durations_min", {1e9}}}}});
    check_problem(r, 422);  // finite but beyond a year: the run would never end
    CHECK(r.body["field"] == "/loading/stage_durations_min/0");
    r = srv.post("/schemes", std::string(R"({"threads": 9223372036854775808})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/threads");
    CHECK(r.body["detail"].get<std::string>().find('-') == std::string::npos);
    r = srv.post("/runs", std::string(R"({"scheme": {}, "threads": 9223372036854775808})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/threads");
    CHECK(r.body["detail"].get<std::string>().find("-9223372036854775808") == std::string::npos);
    r = srv.post("/schemes", json{{"name", std::string(300, 'x')}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/name");
    r = srv.post("/schemes", json{{"loading", {{"stress_levels", std::vector<double>(101, 0.5)}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/loading/stress_levels");
    // Nothing was stored.
    CHECK(srv.get("/schemes").body["schemes"].empty());
}

TEST_CASE("max_particles does not lift the specimen budget: r_min 1e-9 mm is refused at once", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto t0 = std::chrono::steady_clock::now();
    auto r = srv.post("/runs", json{{"scheme", {{"gradation", {{"r_min_mm", 1e-6}}}, {"max_particles", 2000}}}});
    check_problem(r, 422);
    CHECK(r.body["field"] == "/scheme/gradation/r_min_mm");
    CHECK(r.body["detail"].get<std::string>().find("whatever max_particles says") != std::string::npos);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5));
    CHECK(control.started == 0);
}

TEST_CASE("a JSON dataset with kind 5 or a null reading is 422 naming the pointer", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const json curve{{"kind", 5}, {"confining_kPa", 100}, {"columns", {"axial_strain_pct", "q_kPa"}}, {"rows", {{0.5, 80}}}};
    auto r = srv.post("/datasets?format=json", json{{"curves", {curve}}}.dump(), "application/json");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/curves/0/kind");
    json nulls = curve;
    nulls["kind"] = "shear";
    nulls["rows"] = json::parse("[[null, 1], [0.5, 80]]");
    r = srv.post("/datasets?format=json", json{{"curves", {nulls}}}.dump(), "application/json");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/curves/0/rows/0/0");
    r = srv.post("/datasets?format=json", json{{"curves", json::array()}, {"summary", {{{"specimen", 7}}}}}.dump(),
                 "application/json");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/summary/0/specimen");
    CHECK(srv.get("/datasets").body["datasets"].empty());
}

TEST_CASE("POST /packings reads JSON under the same limits: deep nesting, null format, 1e99921 are 422 by field",
          "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    // 400,000 levels (the body limit of the test service is 1 MiB): refused at level 32.
    const auto t0 = std::chrono::steady_clock::now();
    auto r = srv.post("/packings", deep_body(400000));
    check_problem(r, 422);
    CHECK(r.body.value("field", "").rfind("/name/0/0/0", 0) == 0);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(1));
    r = srv.post("/packings", std::string(R"({"format": null})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/format");
    CHECK(r.text.find("json.exception") == std::string::npos);
    r = srv.post("/packings", std::string(R"({"format": "triax-packing", "units": "SI", "particles": {"x_m": [1e99921]}})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/particles/x_m/0");
    CHECK(r.text.find("json.exception") == std::string::npos);
    const std::string grains = R"("particles": {"x_m": [0], "y_m": [0], "z_m": [0], "radius_m": [0.001], "group": [0], "density_kg_m3": [2650]})";
    r = srv.post("/packings", R"({"format": "triax-packing", "units": "SI", "step": "x", )" + grains + "}");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/step");
    r = srv.post("/packings", R"({"format": "triax-packing", "units": "SI", "groups": [null], )" + grains + "}");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/groups/0");
    r = srv.post("/packings", R"({"format": "triax-packing", "units": "SI", "platens": [{"name": 5}], )" + grains + "}");
    check_problem(r, 422);
    CHECK(r.body["field"] == "/platens/0/name");
    r = srv.post("/packings", std::string(R"({"format": "triax-packing", "units": "SI", "particles": {"x_m": [0], "y_m": [0], "z_m": [0], "radius_m": [0.001], "group": [1e12], "density_kg_m3": [2650]}})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/particles/group/0");
    // A valid packing is still taken.
    CHECK(srv.post("/packings", R"({"format": "triax-packing", "units": "SI", )" + grains + "}").status == 201);
}

TEST_CASE("a number beyond a double is 422 naming its field on every JSON route", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    auto r = srv.post("/schemes", std::string(R"({"micro": {"normal_modulus_MPa": 1e99921}})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/micro/normal_modulus_MPa");
    r = srv.post("/runs", std::string(R"({"scheme": {"loading": {"stress_levels": [0.5, -1e400]}}})"));
    check_problem(r, 422);
    CHECK(r.body["field"] == "/scheme/loading/stress_levels/1");
    CHECK(r.text.find("json.exception") == std::string::npos);
}

TEST_CASE("packing names are at most 200 characters, without control characters", "[server][hostile]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const std::string list = "# units: mm\n0 0 0 1\n";
    check_problem(srv.post("/packings?name=" + std::string(201, 'p'), list, "text/plain"), 422);
    check_problem(srv.post("/packings?name=a%0Ab", list, "text/plain"), 422);
    check_problem(srv.post("/packings?name=%FF", list, "text/plain"), 400);
    const auto ok = srv.post("/packings?name=" + std::string(200, 'p'), list, "text/plain");
    CHECK(ok.status == 201);
    // 200 characters of two bytes each are 200 characters.
    std::string greek;
    for (int i = 0; i < 200; ++i) greek += "%CE%B1";
    CHECK(srv.post("/packings?name=" + greek, list, "text/plain").status == 201);
}
