// Snapshots and packings through the service, with the real engine over loopback: a run
// stores the specimen at the end of each stage and serves it in every format; its
// generation snapshot, uploaded as a packing, starts a second run that is the same run;
// a bad packing is refused naming its line.
#include "server/runs/engine_executor.hpp"
#include "service_fixture.hpp"

using namespace triax::test;

namespace {
// The reduced specimen of engine_run_test.cpp (about 40 grains, seconds of engine time).
const json kTinyScheme = json::parse(R"({
  "name": "tiny-snapshots", "seed": 11, "max_particles": 40,
  "specimen": {"diameter_mm": 40, "height_mm": 80},
  "gradation": {"kind": "radius_ratio", "r_min_mm": 2, "radius_ratio": 2},
  "micro": {"membrane_particle_radius_mm": 4},
  "loading": {"confining_pressure_kPa": 100, "stress_levels": [0.3], "stage_durations_min": [1],
              "max_axial_strain_pct": 1}
})");

long long run_to_end(TestServer& srv, const json& body) {
    const auto sub = srv.post("/runs", body);
    INFO(sub.text);
    REQUIRE(sub.status == 202);
    const long long id = sub.body["id"];
    const auto events = srv.events("/runs/" + std::to_string(id) + "/events");
    REQUIRE_FALSE(events.empty());
    INFO(events.back().data.dump());
    REQUIRE(events.back().type == "done");
    return id;
}
}  // namespace

TEST_CASE("a run's snapshots are stored and served, and an exported packing re-imported gives the same run",
          "[server][e2e][engine][snapshots]") {
    TestServer srv(triax::service::make_engine_executor());
    const long long id = run_to_end(srv, json{{"scheme", kTinyScheme}});
    const std::string base = "/runs/" + std::to_string(id) + "/snapshots";

    const auto list = srv.get(base);
    REQUIRE(list.status == 200);
    std::vector<std::string> stages;
    for (const auto& it : list.body["items"]) stages.push_back(it["stage"]);
    CHECK(stages == std::vector<std::string>{"generation", "consolidation", "shear", "creep-1"});
    const auto& first = list.body["items"][0];
    CHECK(first["grains"].get<int>() > 0);
    CHECK(first["grains"].get<int>() <= 40);
    CHECK(first["membrane_particles"].get<int>() > 0);
    CHECK(first["contacts"].get<int>() > 0);

    const auto view = srv.get(base + "/consolidation?format=json");
    REQUIRE(view.status == 200);
    const auto& v = view.body;
    CHECK(v["stage"] == "consolidation");
    const std::size_t n = v["particles"]["x_mm"].size();
    CHECK(n == list.body["items"][1]["grains"].get<std::size_t>() + list.body["items"][1]["membrane_particles"].get<std::size_t>());
    for (const char* k : {"y_mm", "z_mm", "radius_mm", "group", "displacement_mm", "rotation_rad", "crushed"})
        CHECK(v["particles"][k].size() == n);
    CHECK(v["groups"]["0"] == "grain");
    CHECK(v["groups"]["1"] == "membrane");
    const std::size_t m = v["contacts"]["i"].size();
    CHECK(m == list.body["items"][1]["contacts"].get<std::size_t>());
    // Compression positive: a consolidated specimen's grain contacts push.
    double fn_sum = 0.0;
    for (std::size_t k = 0; k < m; ++k) {
        CHECK(v["contacts"]["i"][k].get<int>() < v["contacts"]["j"][k].get<int>());
        CHECK(v["contacts"]["j"][k].get<std::size_t>() < n);
        if (v["particles"]["group"][v["contacts"]["i"][k].get<int>()] == 0) fn_sum += v["contacts"]["normal_force_N"][k].get<double>();
    }
    CHECK(fn_sum > 0.0);
    REQUIRE(v["measurement_spheres"].size() == 3);
    CHECK(v["measurement_spheres"][0]["center_mm"][2].get<double>() == Approx(0.4 * 80.0));
    REQUIRE(v["platens"].size() == 2);
    CHECK(v["platens"][1]["name"] == "top");
    CHECK(v["platens"][1]["normal_force_N"].get<double>() > 0.0);
    // Grains moved during the shear: the shear snapshot's displacements are not all zero.
    const auto shear = srv.get(base + "/shear").body;
    double d_max = 0.0;
    for (const auto& d : shear["particles"]["displacement_mm"]) d_max = std::max(d_max, d.get<double>());
    CHECK(d_max > 0.1);

    for (const char* f : {"spheres", "lammps", "vtk", "project"}) {
        const auto r = srv.get(base + "/generation?format=" + f);
        INFO(f);
        CHECK(r.status == 200);
        CHECK_FALSE(r.text.empty());
    }
    check_problem(srv.get(base + "/generation?format=xyz"), 400);
    check_problem(srv.get(base + "/creep-9"), 404);
    check_problem(srv.get("/runs/999999/snapshots"), 404);

    // The generation snapshot as a packing: the second run starts from the same specimen.
    const auto project = srv.get(base + "/generation?format=project").text;
    const auto up = srv.post("/packings?name=gen", project, "application/json");
    INFO(up.text);
    REQUIRE(up.status == 201);
    CHECK(up.body["grains"] == first["grains"]);
    const long long packing_id = up.body["id"];
    CHECK(srv.get("/packings/" + std::to_string(packing_id)).body["grains"] == first["grains"]);
    const long long id2 = run_to_end(srv, json{{"scheme", kTinyScheme}, {"packing_id", packing_id}});
    const auto s1 = srv.get("/runs/" + std::to_string(id) + "/results/summary").body;
    const auto s2 = srv.get("/runs/" + std::to_string(id2) + "/results/summary").body;
    CHECK(s2["particle_count"] == s1["particle_count"]);
    CHECK(s2["q_failure_kPa"].get<double>() == s1["q_failure_kPa"].get<double>());
    const auto ss1 = srv.get("/runs/" + std::to_string(id) + "/results/stress-strain").body["rows"];
    const auto ss2 = srv.get("/runs/" + std::to_string(id2) + "/results/stress-strain").body["rows"];
    CHECK(ss1 == ss2);
    CHECK(srv.get("/runs/" + std::to_string(id2) + "/snapshots/consolidation").body["particles"] ==
          srv.get(base + "/consolidation").body["particles"]);
}

TEST_CASE("bad packings are refused naming the line or the cause", "[server][snapshots]") {
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    auto detail = [](const Reply& r) { return r.body.value("detail", std::string()); };
    const auto no_unit = srv.post("/packings", "0 0 0 0.001\n", "text/plain");
    check_problem(no_unit, 422);
    CHECK(detail(no_unit).find("line 1") != std::string::npos);
    CHECK(detail(no_unit).find("unit") != std::string::npos);
    const auto bad_number = srv.post("/packings", "# units: mm\n0 0 0 1\n0 0 x 1\n", "text/plain");
    check_problem(bad_number, 422);
    CHECK(detail(bad_number).find("line 3") != std::string::npos);
    CHECK(bad_number.body["line"] == 3);
    check_problem(srv.post("/packings", "# units: furlong\n0 0 0 1\n", "text/plain"), 422);
    check_problem(srv.post("/packings", R"({"format": "triax-packing", "particles": {}})", "application/json"), 422);

    // Stored, then refused against a scheme whose specimen it does not fit.
    const auto up = srv.post("/packings?units=mm", "0 0 0 5\n0 0 7 5\n", "text/plain");
    REQUIRE(up.status == 201);
    const json scheme = {{"name", "small"},
                         {"specimen", {{"diameter_mm", 40}, {"height_mm", 80}}},
                         {"gradation", {{"kind", "radius_ratio"}, {"r_min_mm", 2}, {"radius_ratio", 2}}}};
    const auto overlap = srv.post("/runs", json{{"scheme", scheme}, {"packing_id", up.body["id"]}});
    check_problem(overlap, 422);
    CHECK(detail(overlap).find("line 2") != std::string::npos);
    CHECK(detail(overlap).find("overlaps") != std::string::npos);
    const auto up2 = srv.post("/packings?units=mm", "0 0 0 5\n0 0 60 5\n", "text/plain");
    const auto outside = srv.post("/runs", json{{"scheme", scheme}, {"packing_id", up2.body["id"]}});
    check_problem(outside, 422);
    CHECK(detail(outside).find("line 2") != std::string::npos);
    CHECK(detail(outside).find("outside") != std::string::npos);
    check_problem(srv.post("/runs", json{{"scheme", scheme}, {"packing_id", 99999}}), 404);
}
