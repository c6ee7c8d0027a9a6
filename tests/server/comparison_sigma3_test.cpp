// Comparisons matched by sigma3 and the strength envelope routes, on the scripted run
// (service_fixture.hpp: sigma3 100 kPa, q = 300 (1 - exp(-eps_a / 2)) kPa up to 10 %).
#include "service_fixture.hpp"

#include <cmath>

using namespace triax::test;

namespace {

// The scripted curve + 5 kPa at 100 kPa, and a curve of twice that q at 200 kPa.
std::string two_pressures_csv() {
    std::string csv = "kind,stage,confining_kPa,time_min,axial_strain_pct,axial_deformation_mm,q_kPa\n";
    for (int i = 0; i <= 16; ++i) {
        const double e = 0.3 + 0.6 * i;
        csv += "shear,0,100,," + std::to_string(e) + ",," + std::to_string(script_q_kpa(e) + 5.0) + "\n";
        csv += "shear,0,200,," + std::to_string(e) + ",," + std::to_string(2.0 * script_q_kpa(e)) + "\n";
    }
    return csv;
}

}  // namespace

TEST_CASE("a run is compared with the lab curves at its sigma3, or at the sigma3 asked", "[server][comparison]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "done");
    const long long ds = srv.post("/datasets?name=two&format=csv", two_pressures_csv(), "text/csv").body["id"];

    const auto matched = srv.post("/comparisons", json{{"run_id", run}, {"dataset_id", ds}});
    REQUIRE(matched.status == 201);
    CHECK(matched.body["run_sigma3_kPa"] == 100.0);
    CHECK(matched.body["lab_sigma3_kPa"] == 100.0);
    REQUIRE(matched.body["curves"].size() == 1);
    CHECK(matched.body["curves"][0]["sigma3_kPa"] == 100.0);
    CHECK(matched.body["curves"][0]["rmse"].get<double>() == Approx(5.0).margin(0.05));
    REQUIRE(matched.body["skipped"].size() == 1);
    CHECK(matched.body["skipped"][0]["sigma3_kPa"] == 200.0);
    CHECK(matched.body["skipped"][0]["reason"] == "lab curve at 200 kPa; compared at 100 kPa");
    CHECK(matched.body["warnings"].empty());

    const auto asked = srv.post("/comparisons", json{{"run_id", run}, {"dataset_id", ds}, {"sigma3_kPa", 200}});
    REQUIRE(asked.status == 201);
    REQUIRE(asked.body["curves"].size() == 1);
    CHECK(asked.body["curves"][0]["sigma3_kPa"] == 200.0);
    CHECK(asked.body["warnings"] == json::array({"lab curve at 200 kPa confining vs run at 100 kPa"}));

    const auto none = srv.post("/comparisons", json{{"run_id", run}, {"dataset_id", ds}, {"sigma3_kPa", 300}});
    CHECK(none.status == 422);
    CHECK(none.body["field"] == "/sigma3_kPa");
    CHECK(srv.post("/comparisons", json{{"run_id", run}, {"dataset_id", ds}, {"sigma3_kPa", "100"}}).status == 422);
}

TEST_CASE("GET .../envelope: the dataset's circles and fit, the run's circle through the origin", "[server][envelope]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const long long run = srv.post("/runs", json{{"scheme", json::object()}}).body["id"];
    srv.wait_status(run, "done");
    const long long ds = srv.post("/datasets?name=two&format=csv", two_pressures_csv(), "text/csv").body["id"];

    const auto d = srv.get("/datasets/" + std::to_string(ds) + "/envelope");
    REQUIRE(d.status == 200);
    REQUIRE(d.body["circles"].size() == 2);
    CHECK(d.body["circles"][1]["sigma3_kPa"] == 200.0);
    CHECK(d.body["n_pressures"] == 2);

    // One circle: sigma3 100, q_f the scripted peak at 10 % (the last reading);
    // by hand sin phi' = q_f / (q_f + 2 sigma3).
    const auto r = srv.get("/runs/" + std::to_string(run) + "/envelope");
    REQUIRE(r.status == 200);
    REQUIRE(r.body["circles"].size() == 1);
    const double qf = r.body["circles"][0]["q_peak_kPa"].get<double>();
    CHECK(qf == Approx(script_q_kpa(10.0)).epsilon(0.01));
    CHECK(r.body["friction_angle_deg"].get<double>() ==
          Approx(std::asin(qf / (qf + 200.0)) * 180.0 / 3.14159265358979323846).epsilon(1e-12));
    CHECK(r.body["cohesion_kPa"] == 0.0);
    CHECK(srv.get("/runs/999/envelope").status == 404);
    CHECK(srv.get("/datasets/999/envelope").status == 404);
}
