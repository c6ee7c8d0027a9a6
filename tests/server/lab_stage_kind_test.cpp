// CSV stages without a kind column, read from the physics of their readings: a creep stage
// that begins with its loading ramp, a shear curve that peaks and then plateaus, load steps
// back to back, and files whose readings fit neither. Readings carry seeded lab-like noise
// (q +-0.5 kPa, deformation +-2 um, strain +-0.002 %).
#include "server/io/lab_format.hpp"
#include "server/io/lab_stage_kind.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <sstream>

using namespace triax;

namespace {

std::string csv_error(const std::string& text) {
    try {
        io::parse_lab_csv(text);
    } catch (const io::LabParseError& e) {
        return e.what();
    }
    return "accepted";
}

// Creep on one specimen: stage k loads from the previous level to q_kpa[k] in a ramp of
// `ramp` readings over 1 min, then holds it for 120 min (a reading every 5 min). Test clock
// and cumulative deformation, as a logger writes them; the loading step deforms the
// specimen by 0.1 mm per 60 kPa, the hold by 0.02 k mm ln(1 + t/1 min).
struct StepLoading {
    std::vector<double> q_kpa;
    int ramp = 4;
    double clock0_min = 600.0, deformation0_mm = 0.8;
    std::string text;
    std::vector<double> instant_mm, held_minutes;

    explicit StepLoading(std::vector<double> levels, unsigned seed = 7) : q_kpa(std::move(levels)) {
        std::mt19937 rng(seed);
        std::normal_distribution<double> q_noise(0.0, 0.5), d_noise(0.0, 0.002);
        std::ostringstream out;
        out.precision(10);
        out << "stage,confining_kPa,time_min,axial_deformation_mm,q_kPa\n";
        double t = clock0_min, d = deformation0_mm, q_prev = 0.0;
        for (std::size_t k = 0; k < q_kpa.size(); ++k) {
            const int stage = static_cast<int>(k) + 1;
            const double step_mm = 0.1 * (q_kpa[k] - q_prev) / 60.0;
            for (int j = 0; j < ramp; ++j) {
                const double w = static_cast<double>(j) / ramp;
                out << stage << ",100," << t + w << "," << d + w * step_mm + d_noise(rng) << ","
                    << q_prev + w * (q_kpa[k] - q_prev) + q_noise(rng) << "\n";
            }
            const double t_load = t + 1.0, d_load = d + step_mm;
            instant_mm.push_back(step_mm);
            for (int i = 0; i <= 24; ++i) {
                const double tau = 5.0 * i;
                out << stage << ",100," << t_load + tau << "," << d_load + 0.02 * stage * std::log1p(tau) + d_noise(rng)
                    << "," << q_kpa[k] + q_noise(rng) << "\n";
            }
            held_minutes.push_back(120.0);
            t = t_load + 120.0 + 5.0;
            d = d_load + 0.02 * stage * std::log1p(120.0);
            q_prev = q_kpa[k];
        }
        text = out.str();
    }
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

TEST_CASE("a creep stage that begins with its loading ramp is read as creep from where q is held",
          "[server][lab][stage_kind]") {
    const StepLoading lab({150.0});
    std::vector<std::string> notes;
    const auto d = io::parse_lab_csv(lab.text, &notes);
    REQUIRE(d.curves.size() == 1);
    const auto& c = d.curves[0];
    CHECK(c.kind == diagnose::CurveKind::Creep);
    CHECK(c.stage == 1);
    // The ramp's 4 readings are the loading step, not creep readings.
    REQUIRE(c.size() == 25);
    CHECK(median(c.deviator_pa) == Approx(150e3).epsilon(0.01));
    // Time origin at the first held reading (the logger's clock read 601 min there).
    CHECK(c.time_s.front() == Approx(0.0).margin(1e-9));
    CHECK(c.time_s.back() == Approx(120.0 * 60.0));
    // Deformation from the ramp's first reading: the first held reading is the loading step's
    // deformation (0.25 mm for 150 kPa), the last adds the hold's creep.
    CHECK(c.axial_deformation_m.front() == Approx(0.25e-3).margin(0.01e-3));
    CHECK(c.axial_deformation_m.back() == Approx((0.25 + 0.02 * std::log1p(120.0)) * 1e-3).margin(0.01e-3));
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].find("stage 1 at 100 kPa: read as creep") == 0);
    CHECK(notes[0].find("loading ramp (lines 2-5)") != std::string::npos);
    CHECK(notes[0].find("time from line 6") != std::string::npos);
}

TEST_CASE("a shear curve that peaks and then plateaus is read as shear", "[server][lab][stage_kind]") {
    // Dense sand: q peaks at 1.5 % strain, softens to its residual 220 kPa by 3 % and holds
    // it to 25 %; strain driven at 0.1 %/min. With and without the clock.
    for (const bool timed : {true, false}) {
        INFO((timed ? "with time_min" : "without time"));
        std::mt19937 rng(11);
        std::normal_distribution<double> q_noise(0.0, 0.5), e_noise(0.0, 0.002);
        std::ostringstream out;
        out.precision(10);
        out << "stage,confining_kPa," << (timed ? "time_min," : "") << "axial_strain_pct,q_kPa\n";
        for (int i = 0; i <= 100; ++i) {
            const double e = 0.25 * i;
            const double q = 220.0 * (1.0 - std::exp(-e / 0.3)) + 90.0 * std::exp(-std::pow((e - 1.5) / 0.8, 2));
            out << "3,100," << (timed ? std::to_string(e / 0.1) + "," : "") << e + (i ? e_noise(rng) : 0.0) << ","
                << q + q_noise(rng) << "\n";
        }
        std::vector<std::string> notes;
        const auto d = io::parse_lab_csv(out.str(), &notes);
        REQUIRE(d.curves.size() == 1);
        CHECK(d.curves[0].kind == diagnose::CurveKind::Shear);
        CHECK(d.curves[0].size() == 101);
        CHECK(*std::max_element(d.curves[0].deviator_pa.begin(), d.curves[0].deviator_pa.end()) ==
              Approx(308e3).epsilon(0.01));
        REQUIRE(notes.size() == 1);
        CHECK(notes[0].find("stage 3 at 100 kPa: read as shear (q rises to a peak") == 0);
    }
}

TEST_CASE("creep load steps back to back, each with its ramp, are read as creep stages", "[server][lab][stage_kind]") {
    const StepLoading lab({60.0, 120.0, 180.0}, 3);
    std::vector<std::string> notes;
    const auto d = io::parse_lab_csv(lab.text, &notes);
    REQUIRE(d.curves.size() == 3);
    CHECK(notes.size() == 3);
    for (std::size_t k = 0; k < 3; ++k) {
        INFO("stage " << k + 1);
        const auto& c = d.curves[k];
        CHECK(c.kind == diagnose::CurveKind::Creep);
        CHECK(c.stage == static_cast<int>(k) + 1);
        REQUIRE(c.size() == 25);
        CHECK(median(c.deviator_pa) == Approx(lab.q_kpa[k] * 1e3).epsilon(0.01));
        CHECK(c.time_s.front() == Approx(0.0).margin(1e-9));
        CHECK(c.time_s.back() == Approx(lab.held_minutes[k] * 60.0));
        // Each stage's deformation counts from the level before its own load step.
        CHECK(c.axial_deformation_m.front() == Approx(lab.instant_mm[k] * 1e-3).margin(0.01e-3));
        const double creep_mm = 0.02 * static_cast<double>(k + 1) * std::log1p(120.0);
        CHECK(c.axial_deformation_m.back() - c.axial_deformation_m.front() == Approx(creep_mm * 1e-3).margin(0.01e-3));
    }
}

TEST_CASE("a stage that fits neither shear nor creep is still refused, naming the line and the reason",
          "[server][lab][stage_kind]") {
    // q random under a steadily driven strain.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> q(0.0, 200.0);
    std::string random = "stage,confining_kPa,time_min,axial_strain_pct,q_kPa\n";
    for (int i = 0; i < 40; ++i)
        random += "2,100," + std::to_string(i) + "," + std::to_string(0.1 * i) + "," + std::to_string(q(rng)) + "\n";
    const auto why = csv_error(random);
    CHECK(why.find("line 2, column 1: stage 2 at 100 kPa: cannot tell shear from creep") == 0);
    CHECK(why.find("before reaching the peak at line") != std::string::npos);
    CHECK(why.find("add a kind column") != std::string::npos);

    // Two load steps under one stage number: neither one creep stage nor a shear.
    StepLoading two({60.0, 120.0});
    std::string merged;
    for (std::size_t b = 0, e; b < two.text.size(); b = e + 1) {
        e = two.text.find('\n', b);
        std::string line = two.text.substr(b, e - b);
        if (line.rfind("2,", 0) == 0) line[0] = '1';
        merged += line + "\n";
    }
    const auto steps = csv_error(merged);
    CHECK(steps.find("line 2, column 1: stage 1 at 100 kPa: cannot tell shear from creep") == 0);
    CHECK(steps.find("kPa from line 6 to line 31 and then at") != std::string::npos);
    CHECK(steps.find("several load steps under one stage number") != std::string::npos);
    CHECK(steps.find("add a kind column") != std::string::npos);

    // A ramp and a hold without a deformation column: loading ramp or shear plateau.
    std::string no_deformation = "stage,confining_kPa,time_min,q_kPa\n1,100,0,0\n1,100,1,100\n";
    for (int i = 0; i < 10; ++i) no_deformation += "1,100," + std::to_string(2 + 10 * i) + ",150\n";
    CHECK(csv_error(no_deformation).find("look alike") != std::string::npos);
}

TEST_CASE("the stage classifier's rules on bare readings", "[server][lab][stage_kind]") {
    using V = io::StageKind::Verdict;
    io::StageReadings r;
    // A strain-driven curve that rises to a plateau without a peak: ramp and plateau deform
    // at the same rate, so the plateau is not a hold under load control.
    for (int i = 0; i <= 40; ++i) {
        const double e = 0.5 * i;
        r.q.push_back(200.0 * (1.0 - std::exp(-e / 1.0)));
        r.time.push_back(10.0 * i);
        r.deformation.push_back(e);
        r.line.push_back(i + 2);
    }
    CHECK(io::classify_stage(r).verdict == V::Shear);
    // The same q under load control: the ramp's readings deform 100x faster than the hold.
    io::StageReadings creep;
    for (int i = 0; i <= 40; ++i) {
        const bool ramp = i < 4;
        creep.q.push_back(ramp ? 50.0 * i : 200.0);
        creep.time.push_back(ramp ? 0.25 * i : 1.0 + 10.0 * (i - 4));
        creep.deformation.push_back(ramp ? 0.1 * i : 0.4 + 0.001 * (i - 4));
        creep.line.push_back(i + 2);
    }
    const auto k = io::classify_stage(creep);
    CHECK(k.verdict == V::Creep);
    CHECK(k.hold_begin == 4);
    CHECK(k.held_q == Approx(200.0));
}

TEST_CASE("GDS-Lab export: a creep stage's loading ramp is left out, its clock starts where q is held",
          "[server][lab][stage_kind]") {
    // Stage 1 consolidation (q ~ 0, skipped); stage 2 ramps q to 150 kPa in 60 s, then holds
    // it for 2 h while the specimen creeps.
    std::mt19937 rng(13);
    std::normal_distribution<double> q_noise(0.0, 0.5), d_noise(0.0, 0.002);
    std::ostringstream gds;
    gds.precision(10);
    gds << "Initial Height (mm):,200\n"
           "Stage Number,Time since start of stage (s),Radial Pressure (kPa),Back Pressure (kPa),"
           "Axial Displacement (mm),Deviator Stress (kPa)\n"
           "1,0,300,200,0.00,0.2\n1,600,300,200,0.05,0.3\n";
    for (int j = 0; j < 4; ++j)
        gds << "2," << 15 * j << ",300,200," << 0.05 + 0.3 * j / 4.0 + d_noise(rng) << "," << 150.0 * j / 4.0 + q_noise(rng)
            << "\n";
    for (int i = 0; i <= 24; ++i)
        gds << "2," << 60 + 300 * i << ",300,200," << 0.35 + 0.02 * std::log1p(5.0 * i) + d_noise(rng) << ","
            << 150.0 + q_noise(rng) << "\n";
    const auto d = io::parse_lab_gds(gds.str());
    REQUIRE(d.curves.size() == 1);
    const auto& c = d.curves[0];
    CHECK(c.kind == diagnose::CurveKind::Creep);
    CHECK(c.stage == 1);
    REQUIRE(c.size() == 25);
    CHECK(c.time_s.front() == Approx(0.0).margin(1e-9));
    CHECK(c.time_s.back() == Approx(7200.0));
    // From the last reading of stage 1: the loading step's 0.3 mm stays the first point.
    CHECK(c.axial_deformation_m.front() == Approx(0.3e-3).margin(0.01e-3));
    CHECK(c.axial_strain.front() == Approx(0.3 / 200.0).margin(0.01 / 200.0));
}
