// Creep-law exploration on the reduced CI specimen (or a larger one): runs the creep test
// with parameters overridden on the command line and prints each stage's summary.
// Usage: creep_explore [key=value ...]  keys: A beta sh eps age fc af swf(um) sw dmax b1 b2 fth relax hours seed
//        dmm (specimen diameter mm) rmin_mm ratio first growth cap threads s3 verbose
//        gain (1 adaptive servo gain, 0 base: default) drift (1 the holds' drift criterion, 0 off)
//        qs (1 platen speed capped at the shear test's, 0 off)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "engine/protocol/triaxial_test.hpp"

using namespace triax::protocol;

int main(int argc, char** argv) {
    TestScheme s;
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = 2.5e-3;
    s.gradation.radius_ratio = 3.0;
    s.loading.max_axial_strain = 0.08;
    double hours = 4.0;
    s.creep.first_increment_s = 5.0;
    s.creep.increment_growth = 1.4;
    s.creep.max_increment_s = 1800.0;
    s.seed = 11;
    double sigma3_kpa = 100.0;
    bool verbose = false;
    HoldOptions hold;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        const auto eq = arg.find('=');
        const std::string k = arg.substr(0, eq);
        const double v = std::atof(arg.substr(eq + 1).c_str());
        if (k == "A") s.creep.slip_rate_a_m_s = v;
        else if (k == "beta") s.creep.slip_beta = v;
        else if (k == "sh") s.creep.slip_hardening_length_m = v;
        else if (k == "eps") s.creep.capacity_offset = v;
        else if (k == "age") s.creep.aging_margin = v;
        else if (k == "fc") s.creep.critical_mobilisation = v;
        else if (k == "swf") s.creep.flow_wear_length_m = v * 1e-6;
        else if (k == "af") s.creep.flow_rate_scale = v;
        else if (k == "sw") s.creep.wear_length_m = v;
        else if (k == "b2") s.creep.damage_b2 = v;
        else if (k == "fth") s.creep.damage_threshold = v;
        else if (k == "dmax") s.creep.wear_max = v;
        else if (k == "b1") s.creep.damage_rate_b1_per_s = v;
        else if (k == "relax") s.creep.max_relaxation_per_increment = v;
        else if (k == "hours") hours = v;
        else if (k == "seed") s.seed = static_cast<std::uint64_t>(v);
        else if (k == "dmm") { s.specimen.diameter_m = v / 1000; s.specimen.height_m = 2 * v / 1000; }
        else if (k == "rmin_mm") s.gradation.r_min_m = v / 1000;
        else if (k == "ratio") s.gradation.radius_ratio = v;
        else if (k == "first") s.creep.first_increment_s = v;
        else if (k == "growth") s.creep.increment_growth = v;
        else if (k == "cap") s.creep.max_increment_s = v;
        else if (k == "threads") s.threads = static_cast<int>(v);
        else if (k == "s3") sigma3_kpa = v;
        else if (k == "verbose") verbose = v != 0;
        else if (k == "gain") hold.adaptive_gain = v != 0;
        else if (k == "drift") hold.drift_criterion = v != 0;
        else if (k == "qs") hold.quasi_static_speed = v != 0;
        else if (k == "noov") hold.no_overshoot = v != 0;
        else if (k == "adload") hold.adaptive_loading = v != 0;
        else { std::fprintf(stderr, "unknown key %s\n", k.c_str()); return 2; }
    }
    s.loading.confining_pressure_pa = sigma3_kpa * 1e3;
    s.loading.stage_durations_s.assign(4, hours * 3600.0);
    // verbose=1 prints each creep reading (stage, t min, deformation mm) to stderr.
    struct Trace : RunObserver {
        bool on = false;
        void creep_point(int stage, const CreepPoint& p) override {
            if (on) std::fprintf(stderr, "stage %d t %.1f min d %.4f mm\n", stage, p.time_s / 60, p.axial_deformation_m * 1e3);
        }
    } trace;
    trace.on = verbose;
    const auto r = run_triaxial_test(s, trace, Phase::Creep, hold);
    std::printf("q_f %.1f kPa, grains %d, relaxations %ld, total steps %ld, wall %.1f s\n", r.q_failure_pa / 1e3,
                r.particle_count, r.creep_relaxations, r.total_steps, r.wall_time_s);
    for (const auto& st : r.creep_stages) {
        const double creep = st.final_deformation_m - st.instant_deformation_m;
        std::printf("S=%.2f instant %.4f mm creep %.4f mm elastic %.3f first30 %.2f accel %d conv %d  curve:", st.stress_level,
                    st.instant_deformation_m * 1e3, creep * 1e3, st.elastic_share, st.share_in_first_30min, st.accelerating,
                    st.converged);
        const double marks[] = {60, 600, 1800, 3600, 7200, 0.6 * st.duration_s, 0.8 * st.duration_s, st.duration_s};
        for (double tm : marks) {
            double d = st.translated.front().axial_deformation_m;
            for (const auto& p : st.translated)
                if (p.time_s <= tm + 1e-6) d = p.axial_deformation_m;
            std::printf(" %.4f", (d - st.instant_deformation_m) * 1e3);
        }
        std::printf("\n");
    }
    return 0;
}
