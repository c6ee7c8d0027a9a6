// POST /estimate (what a scheme costs before it is submitted, refusals as for POST
// /schemes) and the page's packages: /vendor/ serves the whitelist from web/node_modules,
// while web/node_modules itself is not served under / or /static/.
#include "service_fixture.hpp"

#include <filesystem>

using namespace triax::test;

TEST_CASE("POST /estimate sizes a preset and follows max_particles", "[server][estimate]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto full = srv.post("/estimate", json{{"preset", "B"}});
    REQUIRE(full.status == 200);
    CHECK(full.body["grains"].get<long long>() > 2000);
    CHECK(full.body["membrane_particles"].get<long long>() > 1000);
    const auto& m = full.body["minutes_estimate"];
    CHECK(m["low"].get<double>() > 0.0);
    CHECK(m["low"].get<double>() <= m["typical"].get<double>());
    CHECK(m["typical"].get<double>() <= m["high"].get<double>());
    CHECK(full.body["steps"].get<long long>() == full.body["steps_by_phase"]["total"]["typical"].get<long long>());
    // Four 2.5-day stages: about 90 increments each (time_schedule.hpp).
    CHECK(full.body["creep_increments"].get<int>() > 300);

    // Wrapped as POST /runs takes it; fewer grains cost fewer minutes.
    const auto small = srv.post("/estimate", json{{"scheme", {{"preset", "B"}, {"max_particles", 150}}}});
    REQUIRE(small.status == 200);
    CHECK(small.body["grains"].get<long long>() <= 160);
    CHECK(small.body["minutes_estimate"]["typical"].get<double>() < m["typical"].get<double>());
    // The automatic membrane holds the smallest grain (7.7 mm): at most 1.2 membrane radii
    // (5 mm spheres, the D/20 cap, lost a grain of B at 150; 6 mm held).
    CHECK(small.body["membrane_particle_radius_mm"].get<double>() >= 6.0);
    CHECK(small.body["membrane_particle_radius_mm"].get<double>() <= 7.7);
    bool few_grains_warned = false;
    for (const auto& w : small.body["warnings"]) few_grains_warned |= w.get<std::string>().find("largest grains across") != std::string::npos;
    CHECK(few_grains_warned);
    // Nothing is stored.
    CHECK(srv.get("/schemes").body["schemes"].empty());
}

TEST_CASE("POST /estimate refuses what POST /schemes refuses, naming the field", "[server][estimate]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto porosity = srv.post("/estimate", json{{"specimen", {{"target_porosity", 1.5}}}});
    CHECK(porosity.status == 422);
    CHECK(porosity.body["field"] == "/specimen/target_porosity");
    // A membrane lattice too fine for the grains: refused with the size to set.
    const json fine = {{"preset", "B"}, {"max_particles", 150}, {"micro", {{"membrane_particle_radius_mm", 5}}}};
    for (const auto& [path, body, field] : {std::tuple{"/estimate", fine, "/micro/membrane_particle_radius_mm"},
                                           std::tuple{"/runs", json{{"scheme", fine}}, "/scheme/micro/membrane_particle_radius_mm"}}) {
        const auto r = srv.post(path, body);
        CHECK(r.status == 422);
        CHECK(r.body["field"] == field);
        CHECK(r.body["detail"].get<std::string>().find("at least") != std::string::npos);
    }
}

TEST_CASE("the page's packages come from /vendor/, the npm tree is not served", "[server][vendor]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto modules = std::filesystem::path(TRIAX_SOURCE_DIR) / "web" / "node_modules";
    if (std::filesystem::exists(modules / "uplot")) {
        const auto u = srv.get("/vendor/uPlot.esm.js");
        CHECK(u.status == 200);
        CHECK(u.content_type.find("javascript") != std::string::npos);
        CHECK(u.text.find("uPlot") != std::string::npos);
    } else {
        CHECK(srv.get("/vendor/uPlot.esm.js").status == 404);  // names scripts/install-deps.sh
    }
    CHECK(srv.get("/vendor/package.json").status == 404);
    CHECK(srv.get("/vendor/..%2Fpackage.json").status == 404);
    CHECK(srv.get("/node_modules/uplot/package.json").status == 404);
    CHECK(srv.get("/static/node_modules/three/package.json").status == 404);
    CHECK(srv.get("/package.json").status == 404);
    CHECK(srv.get("/").status == 200);
}
