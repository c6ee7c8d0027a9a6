#include "engine/protocol/test_scheme.hpp"

#include <cmath>
#include <string>

#include "engine/core/types.hpp"
#include "engine/protocol/gradation.hpp"
#include "engine/protocol/run_estimate.hpp"
#include "engine/protocol/specimen_budget.hpp"

namespace triax::protocol {

namespace {
constexpr double kMaxModulusPa = 1.0e12;            // diamond ~1.2e12
constexpr double kMaxStiffnessNm = 1.0e12;
constexpr double kMaxStageDurationS = 365.25 * 86400.0;

void require(bool ok, const std::string& field, const std::string& why) {
    if (!ok) throw InputError(field + ": " + why);
}
}  // namespace

void TestScheme::validate() const {
    require(specimen.diameter_m > 0.0 && specimen.diameter_m < 2.0, "specimen.diameter_m", "must be in (0, 2) m");
    require(specimen.height_m > 0.0 && specimen.height_m < 4.0, "specimen.height_m", "must be in (0, 4) m");
    require(specimen.target_porosity > 0.2 && specimen.target_porosity < 0.7, "specimen.target_porosity",
            "must be in (0.2, 0.7): random sphere packings cannot reach other values");
    require(specimen.dry_density_kg_m3 > 100.0 && specimen.dry_density_kg_m3 < 5000.0, "specimen.dry_density_kg_m3",
            "must be in (100, 5000) kg/m^3");
    require(specimen.moisture_content >= 0.0 && specimen.moisture_content < 0.5, "specimen.moisture_content",
            "must be in [0, 0.5)");
    size_classes(gradation);  // throws naming the gradation field
    require(gradation_r_max_m(gradation) < 0.25 * specimen.diameter_m, "gradation",
            "largest radius must be below a quarter of the specimen diameter");
    require(micro.friction >= 0.0 && micro.friction < 5.0, "micro.friction", "must be in [0, 5)");
    require(specimen.compaction_friction_ratio >= 0.0 && specimen.compaction_friction_ratio <= 5.0,
            "specimen.compaction_friction_ratio", "must be in [0, 5] (0: frictionless, 1: the grains' friction)");
    require(micro.local_damping >= 0.0 && micro.local_damping < 1.0, "micro.local_damping", "must be in [0, 1)");
    // Upper limits keep the critical time step, and so the run's length, finite.
    require(micro.normal_modulus_pa > 0.0 && micro.normal_modulus_pa <= kMaxModulusPa, "micro.normal_modulus_pa",
            "must be in (0, 1e12] Pa");
    require(micro.shear_modulus_pa > 0.0 && micro.shear_modulus_pa <= kMaxModulusPa, "micro.shear_modulus_pa",
            "must be in (0, 1e12] Pa");
    require(micro.wall_normal_stiffness_n_m > 0.0 && micro.wall_normal_stiffness_n_m <= kMaxStiffnessNm,
            "micro.wall_normal_stiffness_n_m", "must be in (0, 1e12] N/m");
    require(micro.wall_shear_stiffness_n_m >= 0.0 && micro.wall_shear_stiffness_n_m <= kMaxStiffnessNm,
            "micro.wall_shear_stiffness_n_m", "must be in [0, 1e12] N/m");
    require(micro.bond_normal_strength_pa >= 0.0, "micro.bond_normal_strength_pa", "must be >= 0");
    require(micro.bond_shear_strength_pa >= 0.0, "micro.bond_shear_strength_pa", "must be >= 0");
    require(micro.bond_friction >= 0.0 && micro.bond_friction < 5.0, "micro.bond_friction", "must be in [0, 5)");
    require(micro.bond_rolling_friction >= 0.0 && micro.bond_rolling_friction <= 1.0, "micro.bond_rolling_friction",
            "must be in [0, 1] (the neck's half-width over the contact's effective radius)");
    require(micro.membrane_particle_radius_m >= 0.0, "micro.membrane_particle_radius_m", "must be >= 0");
    require(micro.membrane_stiffness_n_m > 0.0 && micro.membrane_stiffness_n_m <= kMaxStiffnessNm,
            "micro.membrane_stiffness_n_m", "must be in (0, 1e12] N/m");
    require(micro.crushing_strength_pa >= 0.0, "micro.crushing_strength_pa", "must be >= 0 (0 = no crushing)");
    require(micro.crushing_reference_diameter_m > 0.0, "micro.crushing_reference_diameter_m", "must be > 0");
    require(micro.crushing_weibull_modulus >= 1.0 && micro.crushing_weibull_modulus <= 50.0,
            "micro.crushing_weibull_modulus", "must be in [1, 50]");
    require(micro.crushing_hardening_ratio >= 0.0 && micro.crushing_hardening_ratio <= 10.0,
            "micro.crushing_hardening_ratio", "must be in [0, 10]");
    require(creep.direct_effect_a >= 1e-4 && creep.direct_effect_a <= 0.1, "creep.direct_effect_a", "must be in [1e-4, 0.1]");
    require(creep.critical_slip_m >= 0.0 && creep.critical_slip_m <= 1e-3, "creep.critical_slip_m", "must be in [0, 1000] um");
    require(creep.renewed_age_s >= 1e-3 && creep.renewed_age_s <= 86400.0, "creep.renewed_age_s", "must be in [0.001, 86400] s");
    require(creep.consolidated_age_s >= 1.0 && creep.consolidated_age_s <= 1e7, "creep.consolidated_age_s", "must be in [1, 1e7] s");
    require(creep.state_exponent_m >= 0.5 && creep.state_exponent_m <= 1.0, "creep.state_exponent_m", "must be in [0.5, 1]");
    require(creep.bond_corrosion_rate_b1_per_s >= 0.0, "creep.bond_corrosion_rate_b1_per_s", "must be >= 0");
    require(creep.max_relaxation_per_increment > 0.0 && creep.max_relaxation_per_increment <= 1.0,
            "creep.max_relaxation_per_increment", "must be in (0, 1]");
    require(creep.first_increment_s > 0.0, "creep.first_increment_s", "must be > 0");
    require(creep.increment_growth >= 1.0, "creep.increment_growth", "must be >= 1");
    require(creep.max_increment_s >= creep.first_increment_s, "creep.max_increment_s", "must be >= first_increment_s");
    require(loading.confining_pressure_pa > 0.0 && loading.confining_pressure_pa < 1.0e8,
            "loading.confining_pressure_pa", "must be in (0, 1e8) Pa");
    for (std::size_t i = 0; i < loading.stress_levels.size(); ++i)
        require(loading.stress_levels[i] > 0.0 && loading.stress_levels[i] < 1.5,
                "loading.stress_levels[" + std::to_string(i) + "]", "must be in (0, 1.5)");
    require(loading.stage_durations_s.size() == loading.stress_levels.size(), "loading.stage_durations_s",
            "needs one duration per stress level");
    for (std::size_t i = 0; i < loading.stage_durations_s.size(); ++i)
        require(loading.stage_durations_s[i] > 0.0 && loading.stage_durations_s[i] <= kMaxStageDurationS,
                "loading.stage_durations_s[" + std::to_string(i) + "]", "must be in (0, 1 year]");
    require(loading.cohesion_pa >= 0.0, "loading.cohesion_pa", "must be >= 0");
    require(loading.friction_angle_deg > 0.0 && loading.friction_angle_deg < 89.0, "loading.friction_angle_deg",
            "must be in (0, 89) deg");
    require(loading.max_axial_strain > 0.0 && loading.max_axial_strain <= 0.4, "loading.max_axial_strain",
            "must be in (0, 0.4]");
    require(loading.max_inertial_number >= 1.0e-5 && loading.max_inertial_number <= 1.0e-2,
            "loading.max_inertial_number", "must be in [1e-5, 1e-2] (quasi-static shear needs I below about 1e-3)");
    require(loading.consolidation_tolerance > 0.0 && loading.consolidation_tolerance < 0.5,
            "loading.consolidation_tolerance", "must be in (0, 0.5)");
    require(threads >= 1 && threads <= 256, "threads", "must be in [1, 256]");
    require(max_particles >= 0, "max_particles", "must be >= 0");
    // Size of the specimen before anything is drawn (specimen_budget.hpp), whatever
    // max_particles says: the builder draws the uncapped gradation first.
    check_specimen_budget(*this);
    // A chosen membrane lattice must hold the grains (run_estimate.hpp).
    check_membrane_holds_grains(*this);
}

}  // namespace triax::protocol
