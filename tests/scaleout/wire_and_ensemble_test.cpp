// The scale-out layer without MPI: a forward run's bytes read back bit for bit, cut
// messages refused with a message, seed lists, and the ensemble statistics on members
// whose curves are known in closed form.
#include <catch2/catch.hpp>

#include <cmath>

#include "server/io/ensemble_json.hpp"
#include "server/scaleout/ensemble.hpp"
#include "server/scaleout/wire_format.hpp"

using namespace triax::diagnose;
using namespace triax::scaleout;

TEST_CASE("a request and an outcome read back bit for bit", "[scaleout]") {
    SimulationRequest r{{{1.0 / 3.0, 2e8, -0.0}, {{Effect::RollingResistance, {0.125}}, {Effect::MoistureBonding, {}}}}, 42};
    const auto back = decode_request(encode_request(r));
    CHECK(back.seed == 42);
    CHECK(back.point.base == r.point.base);
    CHECK(std::signbit(back.point.base[2]));
    CHECK(back.point.effects == r.point.effects);

    SimulationOutcome o;
    o.ok = true;
    o.curves.name = "tiny";
    LabCurve c;
    c.kind = CurveKind::Creep;
    c.stage = 3;
    c.confining_pa = 1e5;
    c.stress_level = 0.8;
    c.time_s = {0.0, 60.0};
    c.axial_strain = {1e-3, 0.1 + 0.2};
    c.axial_deformation_m = {2e-4, 6e-4};
    o.curves.curves = {c};
    o.curves.summary = {{"s1", 1e5, 3e5, 0.02, 0.089, 2000.0, 25e3, 32.0}};
    CHECK(encode_outcome(decode_outcome(encode_outcome(o))) == encode_outcome(o));
    const auto ob = decode_outcome(encode_outcome(o));
    REQUIRE(ob.curves.curves.size() == 1);
    CHECK(ob.curves.curves[0].axial_strain[1] == 0.1 + 0.2);
    CHECK(ob.curves.curves[0].kind == CurveKind::Creep);
    CHECK(ob.curves.summary[0].specimen == "s1");

    SimulationOutcome failed{false, {}, "particle 50 escaped the domain box"};
    const auto fb = decode_outcome(encode_outcome(failed));
    CHECK(!fb.ok);
    CHECK(fb.error == failed.error);
}

TEST_CASE("a cut or padded message is refused with what was cut", "[scaleout]") {
    const auto bytes = encode_request({{{1.0, 2.0}, {}}, 7});
    CHECK_THROWS_WITH(decode_request(bytes.substr(0, bytes.size() - 12)), Catch::Contains("ends inside base parameters"));
    CHECK_THROWS_WITH(decode_request(bytes + "x"), Catch::Contains("bytes left"));
    WireWriter w;
    w.u64(1);
    w.u64(0);
    w.u64(1);
    w.u64(99);  // no such effect
    CHECK_THROWS_WITH(decode_request(w.take()), Catch::Contains("not in the catalog"));
}

TEST_CASE("seed lists: ranges, singles, sorted, refused when malformed", "[scaleout]") {
    CHECK(parse_seed_list("1-3,7,2") == std::vector<std::uint64_t>{1, 2, 3, 7});
    CHECK(parse_seed_list("5") == std::vector<std::uint64_t>{5});
    CHECK_THROWS_WITH(parse_seed_list("5-2"), Catch::Contains("backwards"));
    CHECK_THROWS_WITH(parse_seed_list("a"), Catch::Contains("'a' is not a seed"));
    CHECK_THROWS_WITH(parse_seed_list("1,,2"), Catch::Contains("is not a seed"));
    CHECK_THROWS_WITH(parse_seed_list("1-100000"), Catch::Contains("more than 10000"));
}

TEST_CASE("ensemble: mean and band per grid point over the members that reach it, regime shares", "[scaleout]") {
    // Member a: q = 100 MPa x strain to 2 %; member b: q = 200 MPa x strain to 1 %; c failed.
    EnsembleMember a, b, c;
    a.seed = 2, a.ok = true, a.q_failure_pa = 2e6, a.axial_strain_at_failure = 0.02;
    a.axial_strain = {0.0, 0.02}, a.deviator_pa = {0.0, 2e6}, a.volumetric_strain = {0.0, 0.0};
    b.seed = 1, b.ok = true, b.q_failure_pa = 2e6, b.axial_strain_at_failure = 0.01;
    b.axial_strain = {0.0, 0.01}, b.deviator_pa = {0.0, 2e6}, b.volumetric_strain = {0.0, 0.01};
    MemberStage accelerating{1, 0.8, true, false, true, {0.0, 10.0, 100.0}, {0.0, 0.005, 0.01}};
    MemberStage converged{1, 0.8, false, true, false, {0.0, 10.0, 100.0}, {0.0, 0.001, 0.002}};
    a.stages = {accelerating};
    b.stages = {converged};
    c = member_from_result(3, TaskResult{false, "particle escaped the domain box"});
    CHECK(!c.ok);
    CHECK(c.error == "particle escaped the domain box");

    const auto s = summarise_ensemble("t", {a, b, c});
    CHECK(s.members.front().seed == 1);  // seed order
    CHECK(s.ok == 2);
    REQUIRE(s.shear_axial_strain.size() == 101);
    CHECK(s.shear_axial_strain.back() == Approx(0.02));
    // At 1 % both: 1 and 2 MPa; at 2 % only a (b ends at 1 %).
    CHECK(s.deviator_pa.n[50] == 2);
    CHECK(s.deviator_pa.mean[50] == Approx(1.5e6));
    CHECK(s.deviator_pa.std[50] == Approx(std::sqrt(0.5) * 1e6));
    CHECK(s.deviator_pa.min[50] == Approx(1e6));
    CHECK(s.deviator_pa.max[50] == Approx(2e6));
    CHECK(s.deviator_pa.n[100] == 1);
    CHECK(s.q_failure_pa.mean[0] == Approx(2e6));
    REQUIRE(s.stages.size() == 1);
    CHECK(s.stages[0].reached == 2);
    CHECK(s.stages[0].share_accelerating == Approx(0.5));
    CHECK(s.stages[0].share_converged == Approx(0.5));
    CHECK(s.stages[0].share_ruptured == Approx(0.5));
    CHECK(s.stages[0].share_unsettled == Approx(0.0));
    REQUIRE(s.stages[0].time_s.size() == 101);
    CHECK(s.stages[0].time_s[1] == Approx(10.0));
    CHECK(s.stages[0].time_s.back() == Approx(100.0));
    CHECK(s.stages[0].axial_strain.mean.back() == Approx(0.006));
    const auto j = triax::io::ensemble_to_json(s, true);
    CHECK(j["seeds_ok"] == 2);
    CHECK(j["members"][2]["ok"] == false);
    CHECK(j["q_failure_kPa"]["mean"].get<double>() == Approx(2000.0));
    CHECK(triax::io::shear_band_csv(s).rfind("axial_strain_pct,n_seeds,q_mean_kPa", 0) == 0);
}
