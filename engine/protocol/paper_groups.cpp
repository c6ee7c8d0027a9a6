#include "engine/protocol/paper_groups.hpp"

#include "engine/core/types.hpp"

namespace triax::protocol {

namespace {
// Crushing strength of the paper's grains (disintegrated carbonaceous mudstone;
// docs/protocol.md, "Finding (2)"; with the bonds carrying cohesion the contact forces
// are 40-70 % higher than in a cohesionless fill, whose grains would take 0.6 MPa).
constexpr double kPaperCrushingStrengthPa = 1.0e6;
// The presets' Mohr-Coulomb bonds (the fill's cohesion; Table 1 gives c = 25 kPa) and their
// corrosion rate; the strength was chosen on the creep regimes, not fitted to c
// (docs/creep.md, "Crushing that breaks the bond").
constexpr double kPaperBondStrengthPa = 500.0e3;
constexpr double kPaperBondFriction = 0.4;
constexpr double kPaperBondCorrosionB1PerS = 3.0e-10;
// The bonds' cement neck (docs/creep.md, "The cement neck"): an intact bond holds a rolling
// moment up to (mu_r + 0.6 (1 - D)) Rbar Fn and cracks there.
constexpr double kPaperBondRollingFriction = 0.6;

TestScheme group_scheme(const std::string& name, double sigma3_pa, double moisture) {
    TestScheme s;  // defaults are the paper's Tables 1-3
    s.name = "group " + name;
    s.loading.confining_pressure_pa = sigma3_pa;
    s.specimen.moisture_content = moisture;
    // Full-size DEM gradation (docs/parameters.md, "Paper-group gradation"): the paper's
    // literal Rmin 0.5 mm with Rmax/Rmin 39.712, uniform by number, gives ~140 grains of
    // up to 40 mm in a 100 mm specimen (D/d_max 2.5) and a membrane lattice that small
    // grains pass through. The presets lump the fines at the paper's Eq. 2 weighted-average
    // radius 2.879 mm as Rmin and cap Rmax at 2 Rmin (d_max 11.5 mm, D/d_max 8.7):
    // about 2,700 grains and ~2,200 membrane spheres no smaller than the smallest grain.
    s.gradation.kind = GradationSpec::Kind::RadiusRatio;
    s.gradation.r_min_m = 2.879e-3;
    s.gradation.radius_ratio = 2.0;
    // A cohesive, crushable fill (docs/creep.md, "Crushing that breaks the bond"):
    // - Crushable grains (weak, slaking mudstone): the paper's contraction at 200 kPa
    //   (docs/protocol.md, "Finding (2)"); Weibull modulus and hardening keep the defaults.
    // - The fill's cohesion (Table 1: c = 25 kPa) carried by Mohr-Coulomb bonds (cemented
    //   fines, suction), scaled by the moisture relation for D and E; their strength was
    //   chosen on the creep regimes, not fitted to c. A PFC contact bond of the
    //   scheme default breaks at its shear strength whatever the normal force and adds no
    //   cohesion under compression.
    // - A contact that crushes loses its bond: the cement sits on the asperities that crush.
    // - The bonds' stress corrosion at b1 = 3e-10 1/s, and their cement neck:
    //   an intact bond also holds a rolling moment up to 0.6 (1 - D) Rbar Fn and cracks
    //   there, and the neck's load drives its corrosion. The limit is the normal force's
    //   lever across the neck, a width, not a cement strength: moisture leaves it, and D and
    //   E still differ from B only through the bonds' strengths. The neck's limit grows with the
    //   normal force, so the corrosion clock takes strength that grows with sigma3, which a
    //   clock on the cohesion alone cannot (docs/creep.md, "Where S = 0.8 can go tertiary"
    //   and "The cement neck"). With it S = 0.8 goes tertiary, most often by a collapse that
    //   ends the stage (creep rupture), while S = 0.4 and 0.6 converge, in all five groups on
    //   seed 1; C at 200 kPa still converges on some seeds (docs/creep.md, "The neck in the
    //   presets").
    s.micro.crushing_strength_pa = kPaperCrushingStrengthPa;
    s.micro.crushing_breaks_bond = true;
    s.micro.bond_friction = kPaperBondFriction;
    s.micro.bond_rolling_friction = kPaperBondRollingFriction;
    s.micro.bond_normal_strength_pa = kPaperBondStrengthPa;
    s.micro.bond_shear_strength_pa = kPaperBondStrengthPa;
    s.creep.bond_corrosion_rate_b1_per_s = kPaperBondCorrosionB1PerS;
    // The paper's groups last about 10 days for 4 stages: 2.5 days per stage.
    s.loading.stage_durations_s = {2.5 * 86400.0, 2.5 * 86400.0, 2.5 * 86400.0, 2.5 * 86400.0};
    return s;
}
}  // namespace

std::vector<PaperGroup> paper_groups() {
    return {
        {"A", "sigma3 = 50 kPa, w = 8.9 %, S = 0.1/0.4/0.6/0.8", group_scheme("A", 50.0e3, 0.089)},
        {"B", "sigma3 = 100 kPa, w = 8.9 %, S = 0.1/0.4/0.6/0.8", group_scheme("B", 100.0e3, 0.089)},
        {"C", "sigma3 = 200 kPa, w = 8.9 %, S = 0.1/0.4/0.6/0.8", group_scheme("C", 200.0e3, 0.089)},
        {"D", "sigma3 = 100 kPa, w = 10.2 %, S = 0.1/0.4/0.6/0.8", group_scheme("D", 100.0e3, 0.102)},
        {"E", "sigma3 = 100 kPa, w = 12.1 %, S = 0.1/0.4/0.6/0.8", group_scheme("E", 100.0e3, 0.121)},
    };
}

TestScheme paper_group(const std::string& name) {
    for (auto& g : paper_groups())
        if (g.name == name) return g.scheme;
    throw InputError("group: unknown paper group '" + name + "' (valid: A, B, C, D, E)");
}

}  // namespace triax::protocol
