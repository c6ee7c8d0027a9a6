// The DEM diagnosis on lab curves this engine did not make: a hyperbolic (Duncan-Chang)
// hardening law with a Rowe-type dilatancy at three confining pressures, read to 15 %
// axial strain with noise, as a lab engineer's weak cohesionless fill would look:
//   q(eps) = eps / (1 / E_i + eps / q_ult),  q_ult = q_f / R_f,  q_f from phi (c = 0),
//   E_i = K p_a (sigma3 / p_a)^n,  eps_v = contraction to eps_pt, then dilation at psi.
// Cases: plain, plain + seating 0.3 %, plain + a stick-slip oscillation of q (outside any
// catalog); creep: the plain shear curves and four 4-h creep stages (S 0.2-0.8) per pressure
// with log-time creep; creep_thermal: the same with an hourly thermal cycle of 0.03 % strain
// on the creep readings (outside any catalog). Prints per case the outcome, the verdict, NRMSE before/after, unreached readings,
// runs, and wall time.
// Usage: diagnose_outside_data [case=all|plain|seating|outside|creep|creep_thermal] [budget=12] [refine=3]
//        [grains=200] [rmin_mm=2.5 (1.58: ~760 grains; grains caps)] [concurrency=2] [noise_seeds=3] [effects=1] [candidates=2] [packings=1]
//        [seed=1] (the model's packing seed; the lab curves are the same for every seed)
// (the service's defaults: budget=24 refine=10 effects=3 candidates=3). Each case also
// prints the plan (plan_diagnosis: the most model runs the options allow).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <string_view>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "server/io/diagnosis_verdict.hpp"
#include "bench/key_value_args.hpp"

using namespace triax::diagnose;

namespace {

constexpr double kPi = 3.14159265358979323846;

LabDataset hyperbolic_lab(double seating, double oscillation, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    const double phi = 31.0 * kPi / 180.0, rf = 0.9, K = 300.0, n = 0.5, pa = 101.325e3;
    const double psi = 6.0 * kPi / 180.0, eps_pt = 0.03;
    LabDataset lab;
    lab.name = "hyperbolic fill";
    for (double s3 : {50e3, 100e3, 200e3}) {
        LabCurve c;
        c.kind = CurveKind::Shear;
        c.confining_pa = s3;
        const double qf = 2.0 * s3 * std::sin(phi) / (1.0 - std::sin(phi));
        const double qult = qf / rf, Ei = K * pa * std::pow(s3 / pa, n);
        for (int i = 0; i <= 60; ++i) {
            const double e = 0.0025 * i;
            const double es = std::max(0.0, e - seating);  // the platen closes its gap first
            double q = es / (1.0 / Ei + es / qult);
            q *= 1.0 + oscillation * std::sin(2 * kPi * e / 0.03);
            const double rate = 2.0 * std::sin(psi) / (1.0 - std::sin(psi));
            const double ev = es < eps_pt ? 0.3 * es * (1.0 - es / (2.0 * eps_pt)) : 0.15 * eps_pt - rate * (es - eps_pt);
            c.axial_strain.push_back(e);
            c.deviator_pa.push_back(q + 0.01 * qf * nd(rng));
            c.volumetric_strain.push_back(ev + 2e-4 * nd(rng));
        }
        lab.curves.push_back(std::move(c));
    }
    return lab;
}

// Multi-stage creep of the same fill at each pressure (outside the engine): stage k at
// S_k q_f adds the hyperbola's strain from S_(k-1) q_f to S_k q_f at loading, then creeps
// as C_k log10(1 + t / 1 min), C_k = c (S_k / 0.8)^3 (0.1 % per decade at S = 0.8). Read
// at lab-like times over 4 h per stage, strain from the level before the stage (the
// paper's coordinate translation). `thermal`: an hourly temperature cycle of the cell,
// thermal * sin(2 pi t / 1 h) on every reading (outside any catalog).
void add_creep(LabDataset& lab, double thermal, unsigned seed) {
    std::mt19937_64 rng(seed + 1);
    std::normal_distribution<double> nd(0.0, 1.0);
    const double phi = 31.0 * kPi / 180.0, rf = 0.9, K = 300.0, n = 0.5, pa = 101.325e3;
    const double levels[] = {0.2, 0.4, 0.6, 0.8};
    const double minutes[] = {0, 0.5, 1, 2, 4, 6, 10, 15, 20, 30, 45, 60, 75, 90, 105, 120, 150, 180, 210, 240};
    for (double s3 : {50e3, 100e3, 200e3}) {
        const double qf = 2.0 * s3 * std::sin(phi) / (1.0 - std::sin(phi));
        const double qult = qf / rf, Ei = K * pa * std::pow(s3 / pa, n);
        auto strain_at = [&](double q) { return q / (Ei * (1.0 - q / qult)); };
        double before = 0.0;
        for (int k = 0; k < 4; ++k) {
            LabCurve c;
            c.kind = CurveKind::Creep;
            c.stage = k + 1;
            c.confining_pa = s3;
            c.stress_level = levels[k];
            const double inst = strain_at(levels[k] * qf) - before;
            const double ck = 1e-3 * std::pow(levels[k] / 0.8, 3.0);
            for (double m : minutes) {
                const double t = 60.0 * m;
                const double e = inst + ck * std::log10(1.0 + m) + thermal * std::sin(2 * kPi * t / 3600.0) + 2e-5 * nd(rng);
                c.time_s.push_back(t);
                c.axial_strain.push_back(e);
            }
            before = strain_at(levels[k] * qf);
            lab.curves.push_back(std::move(c));
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> kv{{"case", "all"}, {"budget", "12"}, {"refine", "3"},
                                          {"grains", "200"}, {"rmin_mm", "2.5"}, {"concurrency", "2"}, {"noise_seeds", "3"},
                                          {"effects", "1"}, {"candidates", "2"}, {"packings", "1"},
                                          {"seed", "1"}};
    if (!triax::bench::read_key_values(argc, argv, kv)) return 2;
    DiagnoseOptions opt;
    opt.budget_runs = std::atoi(kv["budget"].c_str());
    opt.refine_runs = std::atoi(kv["refine"].c_str());
    opt.max_effects = std::atoi(kv["effects"].c_str());
    opt.max_candidates = std::atoi(kv["candidates"].c_str());
    opt.concurrency = std::atoi(kv["concurrency"].c_str());
    opt.max_particles = std::atoi(kv["grains"].c_str());
    opt.noise_seeds = std::atoi(kv["noise_seeds"].c_str());
    opt.packings_per_run = std::atoi(kv["packings"].c_str());
    opt.seed = std::strtoull(kv["seed"].c_str(), nullptr, 10);
    opt.finite_difference_uncertainty = false;
    triax::protocol::TestScheme scheme;  // the default scheme: the diagnosis takes the catalog out
    scheme.specimen.diameter_m = 0.05;
    scheme.specimen.height_m = 0.1;
    scheme.gradation.r_min_m = 1e-3 * std::atof(kv["rmin_mm"].c_str());  // 2.5 mm: ~200 grains
    scheme.gradation.radius_ratio = 3.0;
    struct Case {
        const char* name;
        double seating, oscillation;
        bool creep;
        double thermal;
    };
    const Case cases[] = {{"plain", 0.0, 0.0, false, 0.0},       {"seating", 0.003, 0.0, false, 0.0},
                          {"outside", 0.0, 0.15, false, 0.0},    {"creep", 0.0, 0.0, true, 0.0},
                          {"creep_thermal", 0.0, 0.0, true, 3e-4}};
    for (const auto& c : cases) {
        if (kv["case"] != "all" && kv["case"] != c.name) continue;
        LabDataset lab = hyperbolic_lab(c.seating, c.oscillation, 5);
        if (c.creep) add_creep(lab, c.thermal, 5);
        // Progress on stderr: percent, stage and elapsed seconds after every model run.
        struct Progress final : DiagnoseObserver {
            std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
            void on_progress(double percent, std::string_view stage) override {
                const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                std::fprintf(stderr, "  %5.1f %% %-12.*s %6.0f s\n", percent, static_cast<int>(stage.size()), stage.data(), s);
            }
        } quiet;
        const DemForwardModel planned(scheme, lab, opt);
        std::printf("%-8s plan: at most %d model runs\n", c.name, plan_diagnosis(lab, planned, opt).model_runs);
        const auto t0 = std::chrono::steady_clock::now();
        try {
            const auto r = run_diagnosis(lab, scheme, opt, quiet);
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::printf("%-8s outcome %-16s chosen %-22s NRMSE %.1f %% -> %.1f %%  unreached %zu -> %zu  runs %d  wall %.0f s\n",
                        c.name, std::string(outcome_name(r.outcome)).c_str(), r.chosen_effect.c_str(), 100 * r.nrmse_before,
                        100 * r.nrmse_after, r.unreached_before, r.unreached_after, r.runs_used, wall);
            std::printf("         %s\n", triax::io::diagnosis_verdict(r).c_str());
            for (const auto& p : r.parameters) std::printf("         %s = %.4g %s\n", p.name.c_str(), p.value, p.unit.c_str());
            std::printf("         noise floor: packings %.1f %% (%d seeds), readings %.1f %%, tolerance %.1f %%\n",
                        100 * r.noise.model_nrmse, r.noise.seeds, 100 * r.noise.lab_nrmse, 100 * r.noise.tolerance_nrmse);
            for (const auto& [label, v] : r.noise.model_nrmse_per_curve)
                std::printf("           packing scatter %-24s %.1f %%\n", label.c_str(), 100 * v);
            for (std::size_t i = 0; i < r.error_after.size(); ++i) {
                const auto& a = r.error_after[i];
                if (a.phase != "all") continue;
                double before = 0.0;
                for (const auto& b : r.error_before)
                    if (b.curve == a.curve && b.phase == a.phase) before = b.nrmse;
                std::printf("           %-24s NRMSE %.1f %% -> %.1f %%\n", a.curve.c_str(), 100 * before, 100 * a.nrmse);
            }
            // Every effect considered: its signature score, its fit's delta BIC, and why it was
            // or was not kept.
            for (const auto& cd : r.candidates)
                std::printf("           step %d candidate %-24s score %.2f  dBIC %.1f  %s\n", cd.step, cd.effect.c_str(),
                            cd.signature_score, cd.delta_bic_vs_base, cd.note.c_str());
        } catch (const std::exception& e) {
            std::printf("%-8s failed: %s\n", c.name, e.what());
        }
        std::fflush(stdout);
    }
    return 0;
}
