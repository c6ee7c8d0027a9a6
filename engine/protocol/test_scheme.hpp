#pragma once
// TestScheme: everything that defines one triaxial + multi-stage creep test of the seed
// paper. SI units inside (m, Pa, s, kg/m^3, fractions); lab units only at the JSON edge
// (server/io/scheme_json). Defaults are the paper's (Tables 1-3, group B).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/creep/rate_state_params.hpp"

namespace triax::protocol {

struct ImportedPacking;

// Cylindrical specimen (paper: 100 mm x 200 mm, compaction 93 % of 2.21 g/cm^3).
struct SpecimenSpec {
    double diameter_m = 0.1;
    double height_m = 0.2;
    double target_porosity = 0.35;          // n, Table 3
    // Grain friction during the isotropic consolidation as a multiple of micro.friction (the
    // shear's): how a DEM specimen is given its density (PFC's and YADE's friction-controlled
    // compaction). 0: frictionless, the densest packing; 1: the grains' own friction; above
    // 1: looser. The shear and the creep stages run at micro.friction.
    double compaction_friction_ratio = 1.0;
    double dry_density_kg_m3 = 2055.3;      // 0.93 x 2210 (compaction degree x max dry density)
    double moisture_content = 0.089;        // w as a fraction (8.9 % = optimum, Table 1)
    // How sigma3 reaches the soil: the paper's bonded-sphere membrane (Fig. 3B), or the
    // pressure on the outermost grains with no membrane (boundary/grain_pressure.hpp), which
    // adds no lattice confinement (the diagnosis's base, docs/diagnosis.md section 6).
    enum class LateralBoundary { BondedMembrane, GrainPressure };
    LateralBoundary lateral_boundary = LateralBoundary::BondedMembrane;
};

// One point of a sieve curve: grain size (diameter) and mass percent passing.
struct SievePoint {
    double size_m = 0.0;
    double passing_pct = 0.0;
};

// Gradation either from a sieve curve, or the paper's Rmin + Rmax/Rmin ratio (Eq. 3,
// radii uniformly distributed by number as PFC's `ball generate` does). Sieve fractions
// below fines_cutoff_m are lumped into one class at their mass-weighted mean radius (Eq. 2).
struct GradationSpec {
    enum class Kind { RadiusRatio, SieveCurve };
    Kind kind = Kind::RadiusRatio;
    double r_min_m = 0.5e-3;                 // paper: 0.5 mm
    double radius_ratio = 39.712;            // paper: Rmax/Rmin
    std::vector<SievePoint> sieve_curve;     // increasing size, passing in [0, 100]
    double fines_cutoff_m = 1.0e-3;          // paper: grains < 1 mm lumped (diameter)
};

// Micro-parameters (Table 3). Table 3 gives 230.15 and 150.63 without units; we read them
// as the normal and shear effective contact moduli in MPa (docs/parameters.md): the
// linear normal stiffness of a pair is kn = pi * r_eff * E_n / 2 and ks likewise with E_s.
struct MicroParameters {
    double friction = 0.4;                       // mu, particle-particle
    double wall_friction = 0.4;                  // rough platens (porous stones); also stops rigid drift
    double local_damping = 0.7;                  // PFC local damping alpha
    double normal_modulus_pa = 230.15e6;         // Table 3 "230.15" read as MPa
    double shear_modulus_pa = 150.63e6;          // Table 3 "150.63" read as MPa
    double wall_normal_stiffness_n_m = 1.0e8;    // Table 3
    double wall_shear_stiffness_n_m = 1.0e8;     // Table 3
    // Contact bond (soil-soil) strengths at the reference moisture content; scaled by the
    // moisture relation (engine/creep/moisture_bond.hpp). Force = strength x r_min^2.
    double bond_normal_strength_pa = 40.0e3;
    double bond_shear_strength_pa = 40.0e3;
    // Friction of the intact bond's shear strength, ss + bond_friction Fn (Mohr-Coulomb
    // bond, docs/creep.md "Bond cohesion and its corrosion"); 0 = PFC contact bond.
    double bond_friction = 0.0;
    // Cement neck of the intact bond (engine/contact/linear.hpp): it holds a rolling moment
    // below bond_rolling_friction (1 - D) Rbar Fn and cracks there (the bond keeps its
    // cohesion); 0 = no moment (PFC contact bond). docs/creep.md "The cement neck".
    double bond_rolling_friction = 0.0;
    // Membrane: bonded particles of one size, force but no moment.
    double membrane_particle_radius_m = 0.0;     // 0 = automatic (about r_min of the soil, >= 1 mm)
    double membrane_stiffness_n_m = 2.0e4;       // bond spring between membrane particles
    // Rolling resistance mu_r of soil contacts (engine/contact/linear.hpp); 0 = off, as in
    // the paper's linear model. The diagnosis's rolling_resistance effect sets this value.
    double rolling_friction = 0.0;
    // Crushable grain contacts (engine/contact/grain_crushing.hpp, docs/parameters.md):
    // a grain of diameter d crushes locally when a contact force exceeds
    // F_c = sigma0 (d/d0)^(-3/m) (-ln u)^(1/m) d^2 (Weibull, u its survival quantile);
    // beyond it the contact flattens plastically with hardening ratio h >= 0. 0 = off: the
    // scheme default keeps unbreakable grains (with crushing, the reduced creep test's
    // S = 0.6 stage accelerates, docs/protocol.md); the paper-group presets switch it on
    // (engine/protocol/paper_groups.cpp).
    double crushing_strength_pa = 0.0;           // sigma0 at d0
    double crushing_reference_diameter_m = 0.01; // d0
    double crushing_weibull_modulus = 5.0;       // m
    double crushing_hardening_ratio = 0.02;      // h: yield force F_c + h kn delta_p
    // A bonded contact that crushes loses its bond (engine/contact/grain_crushing.hpp).
    bool crushing_breaks_bond = false;
};

// The creep section of a scheme: the time-dependent contact law (engine/creep/
// rate_state_creep.hpp: rate-and-state friction at the contacts, stress corrosion of the
// bonds; its fields and defaults are the law's own) and the stages' physical-time schedule.
struct CreepLawParameters : creep::RateStateParams {
    // Physical-time scheduler.
    double first_increment_s = 1.0;        // first time increment of a creep stage
    double increment_growth = 1.25;        // geometric growth of increments
    double max_increment_s = 3600.0;
    // An increment is split while it would relax more than this share of the specimen's
    // contact shear force at once (the mechanical relaxation must track the creep).
    double max_relaxation_per_increment = 0.02;
};

// Which definition of the stress level drives the creep loads.
enum class StressLevelDefinition { DeviatorRatio /* q / q_f */, PaperEq1 /* Eq. 1, c and phi */ };

struct LoadingSpec {
    double confining_pressure_pa = 100.0e3;
    std::vector<double> stress_levels = {0.1, 0.4, 0.6, 0.8};
    StressLevelDefinition stress_level_definition = StressLevelDefinition::DeviatorRatio;
    double cohesion_pa = 25.0e3;                    // Table 1, for Eq. 1
    double friction_angle_deg = 32.0;               // Table 1, for Eq. 1
    std::vector<double> stage_durations_s = {86400.0, 86400.0, 86400.0, 86400.0};  // physical time per stage (1 day)
    double max_axial_strain = 0.15;
    // The lab's strain rate is not a setting: the density-scaled grains shear at the
    // quasi-static rate this inertial number gives (triaxial_shear.hpp), whatever the lab's.
    // Shear rate as the largest inertial number of the (density-scaled) grains,
    // I = eps_dot d sqrt(rho / p): quasi-static below about 1e-3 (GDR MiDi 2004).
    double max_inertial_number = 5.0e-4;
    // Strain softening ends the shear (a clear peak, then q 20 % below it past 2 % strain),
    // as a lab stops a failed specimen; false: the shear runs to max_axial_strain whatever
    // happens (a calibration against lab readings that go on past the peak).
    bool stop_at_softening = true;
    double consolidation_tolerance = 1.0e-3;        // mean unbalanced / mean contact force
};

// Effects the diagnosis may switch on (defaults off). Physical effects act on the DEM;
// test artefacts act on the measurement (seating, membrane compliance).
struct TestEffects {
    bool accelerated_bond_corrosion = false;       // bonds corrode faster under load (bond degradation)
    double bond_corrosion_scale = 1.0;             // x creep.bond_corrosion_rate_b1_per_s when on
    bool contact_creep_viscosity = true;           // the creep mechanism itself (off = no creep)
    double viscosity_scale = 1.0;                  // multiplies critical_slip and bond_corrosion_rate_b1
    bool moisture_bonding = true;                  // moisture -> bond strength relation
    bool seating_error = false;                    // bedding: extra axial displacement at start of loading
    double seating_displacement_m = 0.5e-3;
    bool membrane_compliance = false;              // membrane hoop stiffness correction on q
    double membrane_modulus_pa = 1.4e6;
    double membrane_thickness_m = 0.5e-3;
};

struct TestScheme {
    std::string name = "custom";
    SpecimenSpec specimen;
    GradationSpec gradation;
    MicroParameters micro;
    CreepLawParameters creep;
    LoadingSpec loading;
    TestEffects effects;
    std::uint64_t seed = 1;
    int threads = 1;
    // Reduced runs for tests: cap of soil particles (0 = no cap: the gradation decides).
    int max_particles = 0;
    // Grains made elsewhere (imported_packing.hpp): when set, they are the specimen and
    // the gradation, target porosity, max_particles and seed's placement are not used.
    std::shared_ptr<const ImportedPacking> packing;

    // Throws InputError naming the field (dotted path, e.g. "specimen.target_porosity").
    void validate() const;
};

}  // namespace triax::protocol
