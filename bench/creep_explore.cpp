// Creep-law exploration on the reduced CI specimen (or a larger one): runs the creep test
// with parameters overridden on the command line and prints each stage's summary.
// Usage: creep_explore [key=value ...]  (keys: bench/reduced_creep_args.hpp; e.g. crush=1
//        for the presets' crushable grains and bonds on the reduced specimen)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/reduced_creep_args.hpp"
#include "engine/diagnose/lab_macro.hpp"
#include "engine/protocol/triaxial_test.hpp"

using namespace triax::protocol;

int main(int argc, char** argv) {
    auto args = triax::bench::reduced_creep_defaults();
    if (!triax::bench::parse_creep_args(args, argc, argv)) return 2;
    const TestScheme& s = args.scheme;
    const bool verbose = args.verbose;
    // verbose=1 prints each creep reading (stage, t min, deformation mm) to stderr.
    struct Trace : RunObserver {
        bool on = false;
        void creep_point(int stage, const CreepPoint& p) override {
            if (on) std::fprintf(stderr, "stage %d t %.1f min d %.4f mm\n", stage, p.time_s / 60, p.axial_deformation_m * 1e3);
        }
        // verbose=2 also prints each physical-time piece (schedule diagnostics).
        bool pieces = false;
        void creep_increment(const CreepIncrementLog& l) override {
            if (pieces)
                std::fprintf(stderr, "piece stage %d t %.2f min dt %.1f s cycles %ld crush %ld d %.4f mm\n", l.stage,
                             l.t_stage_s / 60, l.dt_s, l.hold_cycles, l.crushing_events, l.deformation_m * 1e3);
        }
    } trace;
    trace.pieces = args.verbose_level >= 2;
    trace.on = verbose;
    const auto r = run_triaxial_test(s, trace, args.shear_only ? Phase::Shear : Phase::Creep);
    std::printf("q_f %.1f kPa, grains %d, relaxations %ld, total steps %ld, wall %.1f s\n", r.q_failure_pa / 1e3,
                r.particle_count, r.creep_relaxations, r.total_steps, r.wall_time_s);
    if (args.shear_only) {  // q (kPa) and eps_v (%) at axial strains 1..15 %
        std::printf("q_f at eps_a %.2f %%; eps_a%%:q kPa/eps_v%%", 100 * r.axial_strain_at_failure);
        for (double e : {0.01, 0.02, 0.03, 0.04, 0.06, 0.08, 0.10, 0.12, 0.15})
            for (const auto& p : r.shear)
                if (p.axial_strain >= e) {
                    std::printf(" %.0f:%.0f/%.2f", 100 * e, p.q_pa / 1e3, 100 * p.volumetric_strain);
                    break;
                }
        std::printf("\n");
    }
    for (const auto& st : r.creep_stages) {
        const double creep = st.final_deformation_m - st.instant_deformation_m;
        std::printf("S=%.2f instant %.4f mm creep %.4f mm elastic %.3f first30 %.2f (total %.2f) accel %d conv %d rupt %.1f h  curve:",
                    st.stress_level, st.instant_deformation_m * 1e3, creep * 1e3, st.elastic_share,
                    st.share_in_first_30min, st.total_share_in_first_30min, st.accelerating,
                    st.converged, st.ruptured ? st.rupture_time_s / 3600.0 : -1.0);
        const double marks[] = {60, 600, 1800, 3600, 7200, 0.6 * st.duration_s, 0.8 * st.duration_s, st.duration_s};
        for (double tm : marks) {
            double d = st.translated.front().axial_deformation_m;
            for (const auto& p : st.translated)
                if (p.time_s <= tm + 1e-6) d = p.axial_deformation_m;
            std::printf(" %.4f", (d - st.instant_deformation_m) * 1e3);
        }
        // Creep strain per decade of time (% of the height): least-squares slope of the strain
        // against log10 t over [t0, t1]: all (1 min-end, the diagnosis's lab figure, lab_macro.hpp);
        // early (1 min-1 h) and late (1 h-end) show whether the
        // creep is logarithmic in time (equal slopes).
        std::vector<double> times, strains_pct;
        for (const auto& p : st.translated) {
            times.push_back(p.time_s);
            strains_pct.push_back(100.0 * p.axial_strain);
        }
        auto per_decade = [&](double t0, double t1) {
            return triax::diagnose::creep_strain_per_decade(times, strains_pct, t0, t1 + 1e-6);
        };
        std::printf("  per-decade %% all %.4f early %.4f late %.4f", per_decade(60.0, st.duration_s),
                    per_decade(60.0, 3600.0), per_decade(3600.0, st.duration_s));
        // Breakage energy dissipated during the stage (crushing).
        double b0 = -1.0, b1 = 0.0;
        for (const auto& e : r.energies)
            if (e.phase_index == 1 + st.stage) {
                if (b0 < 0.0) b0 = e.breakage_j;
                b1 = e.breakage_j;
            }
        std::printf("  breakage %.3g mJ\n", 1e3 * (b1 - std::max(b0, 0.0)));
    }
    return 0;
}
