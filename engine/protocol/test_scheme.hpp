#pragma once
// TestScheme: everything that defines one triaxial + multi-stage creep test of the seed
// paper. SI units inside (m, Pa, s, kg/m^3, fractions); lab units only at the JSON edge
// (server/io/scheme_json). Defaults are the paper's (Tables 1-3, group B).
#include <cstdint>
#include <string>
#include <vector>

namespace triax::protocol {

// Cylindrical specimen (paper: 100 mm x 200 mm, compaction 93 % of 2.21 g/cm^3).
struct SpecimenSpec {
    double diameter_m = 0.1;
    double height_m = 0.2;
    double target_porosity = 0.35;          // n, Table 3
    double dry_density_kg_m3 = 2055.3;      // 0.93 x 2210 (compaction degree x max dry density)
    double moisture_content = 0.089;        // w as a fraction (8.9 % = optimum, Table 1)
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
    // A bond cemented under load (engine/protocol/specimen.cpp, install_soil_bonds): its
    // normal and shear strengths (forces) gain this multiple of the contact's normal force
    // when the bond forms after consolidation, so the cohesion grows with the consolidation
    // stress (the cement fills a contact flat that the load made); 0 = strength from
    // bond_*_strength_pa alone. docs/creep.md "A bond cemented under load".
    double bond_load_ratio = 0.0;
    // Membrane: bonded particles of one size, force but no moment.
    double membrane_particle_radius_m = 0.0;     // 0 = automatic (about r_min of the soil, >= 1 mm)
    double membrane_stiffness_n_m = 2.0e4;       // bond spring between membrane particles
    // Rolling resistance (off by default: paper uses the linear model).
    double rolling_friction = 0.0;               // mu_r, 0 = off
    // Crushable grain contacts (engine/contact/grain_crushing.hpp, docs/parameters.md):
    // a grain of diameter d crushes locally when a contact force exceeds
    // F_c = sigma0 (d/d0)^(-3/m) (-ln u)^(1/m) d^2 (Weibull, u its survival quantile);
    // beyond it the contact flattens plastically with hardening ratio h. 0 = off: the
    // scheme default keeps unbreakable grains (with crushing, the reduced creep test's
    // S = 0.6 stage accelerates, docs/protocol.md); the paper-group presets switch it on
    // (engine/protocol/paper_groups.cpp).
    double crushing_strength_pa = 0.0;           // sigma0 at d0
    double crushing_reference_diameter_m = 0.01; // d0
    double crushing_weibull_modulus = 5.0;       // m
    double crushing_hardening_ratio = 0.02;      // h (< 0: the yield force falls as the grain crushes)
    double crushing_residual_ratio = 0.0;        // rho: where a softening (h < 0) contact's yield force ends, x F_c
    // A crushed contact's friction drops to mu (1 - loss): its fragments roll and lose
    // their interlocking (0 = kept; docs/creep.md "Bonds in the presets' crushable skeleton").
    double crushing_friction_loss = 0.0;
    // A bonded contact that crushes loses its bond (engine/contact/grain_crushing.hpp).
    bool crushing_breaks_bond = false;
};

// Time-dependent contact mechanism (docs/creep.md): rate-process delayed slip at the
// frictional contacts with asperity wear (slip weakening), plus stress corrosion of the
// contact bonds.
// Drive of the grains' static fatigue (GrainFatigueParams::drive in grain_crushing.hpp).
enum class GrainFatigueDrive { CappedPeakForce, PeakForce, GrainStress };

struct CreepLawParameters {
    // Rate process: slip rate v = v0 * exp(-dE/kT) * sinh(f / f_ref) applied to the
    // mobilised friction ratio f = |Fs| / (mu Fn). Lumped here as v = A sinh(beta f).
    double slip_rate_a_m_s = 5.0e-21;      // A (m/s): rate at sliding ~ A e^beta / 2 = 2.7e-8 m/s
    double slip_beta = 30.0;               // beta = mu / a of rate-and-state friction (docs/creep.md)
    // Delayed-slip capacity s_eq = s_h f / (1 - f + eps) (docs/creep.md).
    double slip_hardening_length_m = 2.0e-6;   // s_h
    double capacity_offset = 0.5;              // eps: capacity at sliding is s_h / eps
    // Contact aging: a contact held for a stage (or the consolidation) bears this rise of
    // its mobilisation before it creeps again (static friction grows with hold time).
    double aging_margin = 0.2;
    // Secondary flow: a contact at mobilisation f >= f_c slips steadily at A_f sinh(beta f)
    // with no capacity, until its spring relaxes f to f_c (docs/creep.md); > 1 = off.
    // Off by default: with it on, the reduced specimen's S = 0.1 - 0.6 stages stop
    // converging before S = 0.8 accelerates (docs/creep.md, measured table).
    double critical_mobilisation = 2.0;
    // The flow's rate A_f = flow_rate_scale * A: a slow secondary process next to the
    // delayed slip (docs/creep.md).
    double flow_rate_scale = 1.0e-3;
    // Asperity wear by creep slip: D = D_max (1 - exp(-slip / s_w)), friction mu (1 - D).
    double wear_length_m = 20.0e-6;        // s_w
    double wear_max = 0.5;                 // D_max
    // A flowing contact (f >= f_c) wears over this shorter length (docs/creep.md).
    double flow_wear_length_m = 2.0e-6;    // s_wf
    // Slow-slip weakening: a contact that slides during a creep hold (at creep rates) loses
    // up to this share of its friction over the sliding length d_c (rate-and-state steady
    // state of velocity-strengthening gouge, docs/creep.md); 0 = off.
    double slow_slip_wear_max = 0.0;       // D_s
    double slow_slip_wear_length_m = 20.0e-6;  // d_c
    // Stress corrosion of contact bonds: dD/dt = b1 exp(b2 rho) when rho > threshold,
    // rho = bond load / bond strength.
    double damage_rate_b1_per_s = 1.0e-9;
    double damage_b2 = 10.0;
    double damage_threshold = 0.9;
    // A bond that broke after corroding leaves its weathered cement as clay gouge: the
    // contact's friction drops to mu (1 - loss) (docs/creep.md, equation 4); 0 = off.
    double corroded_bond_friction_loss = 0.0;
    // Static fatigue of crushable grains (delayed crushing; grain_crushing.hpp,
    // docs/creep.md): dD/dt = (1/t0) (F_max / (F_c (1 - D)))^n per grain, crushing force
    // F_c (1 - D). Acts in creep stages only, and only when micro.crushing_strength_pa > 0.
    double grain_fatigue_time_s = 0.0;     // t0; 0 = off
    double grain_fatigue_exponent = 20.0;  // n (Charles' law exponent, rock 10-40)
    // Cap on the force ratio r = F_max / F_c that drives the fatigue. 1: a grain loaded
    // beyond its intact strength (a hardened, flattened contact) fatigues like one at its
    // strength; > 1: at F/F_c (McDowell's characteristic stress F/d^2 grows with F), so a
    // grain that takes a broken neighbour's load fatigues faster (fibre-bundle load sharing).
    double grain_fatigue_ratio_cap = 1.0;
    // What drives a grain's fatigue (grain_crushing.hpp, docs/creep.md "Load-dependent
    // fatigue drive"): its peak contact force capped at its strength (default, the law
    // above), uncapped, or its splitting drive from the grain's average stress tensor,
    // F_eq = (pi d^2 / 6)(sigma_1 - sigma_3), uncapped.
    GrainFatigueDrive grain_fatigue_drive = GrainFatigueDrive::CappedPeakForce;
    // Grains whose life at the present forces is shorter than this fail at once, in one
    // relaxation, repeated while any remain (instantaneous crushing); 0 = off.
    double grain_fatigue_instant_life_s = 0.0;
    // Spread of lives from the brittle lifetime law: t0_i = t0 (S_i / sigma0)^-2.
    bool grain_fatigue_strength_spread = false;
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
    double shear_strain_rate_per_s = 1.0e-4 / 60.0; // lab rate (0.01 %/min), mapped to a quasi-static DEM rate
    double max_axial_strain = 0.15;
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
    bool rolling_resistance = false;
    double rolling_friction = 0.1;
    bool grain_breakage = false;                   // bond degradation under load (extra damage)
    double breakage_damage_scale = 1.0;
    bool contact_creep_viscosity = true;           // the creep mechanism itself (off = no creep)
    double viscosity_scale = 1.0;                  // multiplies slip_rate_a and damage_rate_b1
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

    // Throws InputError naming the field (dotted path, e.g. "specimen.target_porosity").
    void validate() const;
};

}  // namespace triax::protocol
