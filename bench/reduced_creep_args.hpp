#pragma once
// Shared set-up of the creep bench programs (creep_explore, paper_group_increment_check):
// the reduced CI creep specimen of tests/protocol/triaxial_protocol_test.cpp and the
// key=value overrides they accept. One place, so the two programs run the same specimen.
// Keys: group (A-E: the full-size paper group, given first) h4 (the last stage's hours) a dc tr m (the rate-and-state law: a, D_c in m, renewed age in s, m = b / a) b1 b2 fth
//       bmu (bond friction) brf (bond rolling friction: the cement neck) bss bns (bond shear/normal strength, kPa) sigc (crushing strength, MPa;
//       0 = unbreakable) wm (its Weibull modulus) ch (its hardening ratio) cbb (1: a crushing contact loses its bond) relax seed dmm rmin_mm
//       ratio first growth cap threads gp (1: grain-pressure boundary) crush(1 = the paper-group presets' micro-parameters: bonds and
//       crushable grains) s3(kPa) hours shear (1: no creep) verbose
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::bench {

struct ReducedCreepArgs {
    protocol::TestScheme scheme;
    double hours = 4.0;         // each of the 4 stages
    double last_hours = 0.0;    // the last stage's, if > 0 (key h4)
    double sigma3_kpa = 100.0;
    bool verbose = false;
    int verbose_level = 0;  // verbose=2: also the per-piece schedule log
    bool shear_only = false;  // shear=1: consolidation and shear only (q_f, no creep)
};

// The reduced creep specimen (50 x 100 mm, ~200 grains, 4-h stages, seed 11).
inline ReducedCreepArgs reduced_creep_defaults() {
    ReducedCreepArgs a;
    auto& s = a.scheme;
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.gradation.r_min_m = 2.5e-3;
    s.gradation.radius_ratio = 3.0;
    s.loading.max_axial_strain = 0.08;
    s.creep.first_increment_s = 5.0;
    s.creep.increment_growth = 1.4;
    s.creep.max_increment_s = 1800.0;
    s.seed = 11;
    return a;
}

// Applies one key=value argument; false (and a message naming it) for an unknown key.
inline bool apply_creep_arg(ReducedCreepArgs& a, const std::string& arg) {
    auto& s = a.scheme;
    const auto eq = arg.find('=');
    if (eq == std::string::npos) {
        std::fprintf(stderr, "argument '%s': expected key=value\n", arg.c_str());
        return false;
    }
    const std::string k = arg.substr(0, eq);
    const double v = std::atof(arg.substr(eq + 1).c_str());
    if (k == "group") {  // the paper group's full-size scheme (e.g. group=B); give it first
        try {
            s = protocol::paper_group(arg.substr(eq + 1));
        } catch (const std::exception& e) {  // the preset lookup names the valid groups
            std::fprintf(stderr, "%s\n", e.what());
            return false;
        }
        a.sigma3_kpa = s.loading.confining_pressure_pa / 1e3;
        a.hours = s.loading.stage_durations_s.empty() ? a.hours : s.loading.stage_durations_s.front() / 3600.0;
    }
    else if (k == "a") s.creep.direct_effect_a = v;
    else if (k == "dc") s.creep.critical_slip_m = v;
    else if (k == "tr") s.creep.renewed_age_s = v;
    else if (k == "m") s.creep.state_exponent_m = v;
    else if (k == "b2") s.creep.bond_corrosion_b2 = v;
    else if (k == "fth") s.creep.bond_corrosion_threshold = v;
    else if (k == "b1") s.creep.bond_corrosion_rate_b1_per_s = v;
    else if (k == "bmu") s.micro.bond_friction = v;
    else if (k == "brf") s.micro.bond_rolling_friction = v;
    else if (k == "sigc") s.micro.crushing_strength_pa = v * 1e6;
    else if (k == "wm") s.micro.crushing_weibull_modulus = v;
    else if (k == "ch") s.micro.crushing_hardening_ratio = v;
    else if (k == "cbb") s.micro.crushing_breaks_bond = v != 0;
    else if (k == "bss") s.micro.bond_shear_strength_pa = v * 1e3;
    else if (k == "bns") s.micro.bond_normal_strength_pa = v * 1e3;
    else if (k == "relax") s.creep.max_relaxation_per_increment = v;
    else if (k == "crush") { if (v != 0) s.micro = protocol::paper_group("C").micro; }
    else if (k == "hours") a.hours = v;
    else if (k == "h4") a.last_hours = v;
    else if (k == "shear") a.shear_only = v != 0;
    else if (k == "seed") s.seed = static_cast<std::uint64_t>(v);
    else if (k == "gp")  // 1: the grain-pressure lateral boundary (no membrane), the diagnosis's base
        s.specimen.lateral_boundary = v != 0 ? protocol::SpecimenSpec::LateralBoundary::GrainPressure
                                             : protocol::SpecimenSpec::LateralBoundary::BondedMembrane;
    else if (k == "dmm") { s.specimen.diameter_m = v / 1000; s.specimen.height_m = 2 * v / 1000; }
    else if (k == "rmin_mm") s.gradation.r_min_m = v / 1000;
    else if (k == "ratio") s.gradation.radius_ratio = v;
    else if (k == "first") s.creep.first_increment_s = v;
    else if (k == "growth") s.creep.increment_growth = v;
    else if (k == "cap") s.creep.max_increment_s = v;
    else if (k == "threads") s.threads = static_cast<int>(v);
    else if (k == "s3") a.sigma3_kpa = v;
    else if (k == "verbose") { a.verbose = v != 0; a.verbose_level = static_cast<int>(v); }
    else {
        std::fprintf(stderr, "unknown key %s\n", k.c_str());
        return false;
    }
    return true;
}

// Parses argv[first..] and fills the loading (sigma3, 4 stages of `hours`).
inline bool parse_creep_args(ReducedCreepArgs& a, int argc, char** argv, int first = 1) {
    for (int k = first; k < argc; ++k)
        if (!apply_creep_arg(a, argv[k])) return false;
    a.scheme.loading.confining_pressure_pa = a.sigma3_kpa * 1e3;
    a.scheme.loading.stage_durations_s.assign(4, a.hours * 3600.0);
    if (a.last_hours > 0.0) a.scheme.loading.stage_durations_s.back() = a.last_hours * 3600.0;
    return true;
}

}  // namespace triax::bench
