// GET /datasets/{id} sends the stored readings as they are stored, in slices read from the
// store: a 15 MB upload once cost 100 MB of memory per read (parsed, copied, dumped) and
// ten concurrent reads held 1.7 GB. The answer keeps its form: the header fields and "data".
#include "service_fixture.hpp"

using namespace triax::test;

namespace {
std::string csv_rows(int n) {
    std::string csv = "confining_kPa,axial_strain_pct,q_kPa\n";
    for (int i = 1; i <= n; ++i) csv += "100," + std::to_string(i * 1e-3) + "," + std::to_string(80 + i % 97) + "\n";
    return csv;
}
}  // namespace

TEST_CASE("GET /datasets/{id} serves the stored text without parsing it", "[server][datasets]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto up = srv.post("/datasets?format=csv&name=tiny", csv_rows(3), "text/csv");
    REQUIRE(up.status == 201);
    const std::string path = "/datasets/" + std::to_string(up.body["id"].get<long long>());
    const auto before = srv.get(path);
    REQUIRE(before.status == 200);
    CHECK(before.body["name"] == "tiny");
    CHECK(before.body["format"] == "csv");
    CHECK(before.body["curves"] == up.body["curves"]);
    CHECK(before.body["data"]["curves"][0]["rows"].size() == 3);
    // A stored text the lab reader would refuse is still sent as stored: it is not parsed.
    srv.service().db.with(
        [](triax::service::Database& db) { db.exec(R"(UPDATE datasets SET dataset_json = '{"curves": "as stored"}')"); });
    const auto after = srv.get(path);
    REQUIRE(after.status == 200);
    CHECK(after.body["data"] == json{{"curves", "as stored"}});
    CHECK(after.body["curves"] == up.body["curves"]);  // from the stored header
    check_problem(srv.get("/datasets/99"), 404);
}

TEST_CASE("a 4 MB dataset reads back whole through the slices, with a Content-Length", "[server][datasets]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control), {}, 1, 8,
                   [](triax::service::ServiceConfig& c) { c.max_body_bytes = 16u << 20; });
    const int rows = 200000;
    const std::string csv = csv_rows(rows);
    REQUIRE(csv.size() > 3u << 20);
    const auto up = srv.post("/datasets?format=csv", csv, "text/csv");
    REQUIRE(up.status == 201);
    auto c = srv.client();
    const auto r = c.Get(("/datasets/" + std::to_string(up.body["id"].get<long long>())).c_str());
    REQUIRE(r);
    REQUIRE(r->status == 200);
    CHECK(r->get_header_value("Content-Length") == std::to_string(r->body.size()));
    const json doc = json::parse(r->body);
    const auto& curve = doc["data"]["curves"][0];
    REQUIRE(curve["rows"].size() == static_cast<std::size_t>(rows));
    const auto& cols = curve["columns"];
    const auto strain = std::find(cols.begin(), cols.end(), json("axial_strain_pct")) - cols.begin();
    REQUIRE(strain < static_cast<std::ptrdiff_t>(cols.size()));
    CHECK(curve["rows"][rows - 1][static_cast<std::size_t>(strain)].get<double>() == Approx(rows * 1e-3));
    CHECK(doc["id"] == up.body["id"]);
}
