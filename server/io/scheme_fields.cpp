#include "server/io/scheme_fields.hpp"

#include "engine/protocol/paper_groups.hpp"

namespace triax::io {

using nlohmann::ordered_json;
using protocol::TestScheme;

const std::vector<NumberField>& number_fields() {
    static const std::vector<NumberField> f = {
        {"specimen", "diameter_mm", "specimen.diameter_m", [](TestScheme& s) -> double& { return s.specimen.diameter_m; }, 1e-3, {}, nullptr},
        {"specimen", "height_mm", "specimen.height_m", [](TestScheme& s) -> double& { return s.specimen.height_m; }, 1e-3, {}, nullptr},
        {"specimen", "target_porosity", "specimen.target_porosity", [](TestScheme& s) -> double& { return s.specimen.target_porosity; }, 1.0, {.above = 0.2, .below = 0.7}, nullptr},
        {"specimen", "compaction_friction_ratio", "specimen.compaction_friction_ratio", [](TestScheme& s) -> double& { return s.specimen.compaction_friction_ratio; }, 1.0, {.min = 0, .max = 5}, "grain friction during consolidation as a multiple of micro.friction: 0 = frictionless (densest), 1 = the grains' own; the shear runs at micro.friction"},
        {"specimen", "dry_density_g_cm3", "specimen.dry_density_kg_m3", [](TestScheme& s) -> double& { return s.specimen.dry_density_kg_m3; }, 1000.0, {}, nullptr},
        {"specimen", "moisture_content_pct", "specimen.moisture_content", [](TestScheme& s) -> double& { return s.specimen.moisture_content; }, 0.01, {.above = 0, .below = 50}, nullptr},
        {"gradation", "r_min_mm", "gradation.r_min_m", [](TestScheme& s) -> double& { return s.gradation.r_min_m; }, 1e-3, {}, nullptr},
        {"gradation", "radius_ratio", "gradation.radius_ratio", [](TestScheme& s) -> double& { return s.gradation.radius_ratio; }, 1.0, {}, nullptr},
        {"gradation", "fines_cutoff_mm", "gradation.fines_cutoff_m", [](TestScheme& s) -> double& { return s.gradation.fines_cutoff_m; }, 1e-3, {}, nullptr},
        {"micro", "friction", "micro.friction", [](TestScheme& s) -> double& { return s.micro.friction; }, 1.0, {}, nullptr},
        {"micro", "wall_friction", "micro.wall_friction", [](TestScheme& s) -> double& { return s.micro.wall_friction; }, 1.0, {}, nullptr},
        {"micro", "local_damping", "micro.local_damping", [](TestScheme& s) -> double& { return s.micro.local_damping; }, 1.0, {.above = 0, .below = 1}, nullptr},
        {"micro", "normal_modulus_MPa", "micro.normal_modulus_pa", [](TestScheme& s) -> double& { return s.micro.normal_modulus_pa; }, 1e6, {}, nullptr},
        {"micro", "shear_modulus_MPa", "micro.shear_modulus_pa", [](TestScheme& s) -> double& { return s.micro.shear_modulus_pa; }, 1e6, {}, nullptr},
        {"micro", "wall_normal_stiffness_N_m", "micro.wall_normal_stiffness_n_m", [](TestScheme& s) -> double& { return s.micro.wall_normal_stiffness_n_m; }, 1.0, {}, nullptr},
        {"micro", "wall_shear_stiffness_N_m", "micro.wall_shear_stiffness_n_m", [](TestScheme& s) -> double& { return s.micro.wall_shear_stiffness_n_m; }, 1.0, {}, nullptr},
        {"micro", "bond_normal_strength_kPa", "micro.bond_normal_strength_pa", [](TestScheme& s) -> double& { return s.micro.bond_normal_strength_pa; }, 1e3, {}, nullptr},
        {"micro", "bond_shear_strength_kPa", "micro.bond_shear_strength_pa", [](TestScheme& s) -> double& { return s.micro.bond_shear_strength_pa; }, 1e3, {}, nullptr},
        {"micro", "bond_friction", "micro.bond_friction", [](TestScheme& s) -> double& { return s.micro.bond_friction; }, 1.0, {.min = 0}, "friction of an intact soil bond's shear strength: it breaks at shear strength x pi r_min^2 + bond_friction x normal force (Mohr-Coulomb bond); 0 = PFC contact bond"},
        {"micro", "bond_rolling_friction", "micro.bond_rolling_friction", [](TestScheme& s) -> double& { return s.micro.bond_rolling_friction; }, 1.0, {.min = 0, .max = 1}, "cement neck of an intact soil bond: it also holds a rolling moment below bond_rolling_friction x (1 - corrosion damage) x effective radius x normal force, and the neck cracks there (the bond keeps its cohesion, the contact then holds no moment); 0 = the bond transmits no moment (PFC contact bond)"},
        {"micro", "membrane_particle_radius_mm", "micro.membrane_particle_radius_m", [](TestScheme& s) -> double& { return s.micro.membrane_particle_radius_m; }, 1e-3, {}, nullptr},
        {"micro", "membrane_stiffness_N_m", "micro.membrane_stiffness_n_m", [](TestScheme& s) -> double& { return s.micro.membrane_stiffness_n_m; }, 1.0, {}, nullptr},
        {"micro", "rolling_friction", "micro.rolling_friction", [](TestScheme& s) -> double& { return s.micro.rolling_friction; }, 1.0, {}, "rolling resistance mu_r of soil contacts: the rolling moment is held below mu_r x effective radius x normal force; 0 = off (the paper's linear model). The diagnosis's rolling_resistance effect sets it"},
        {"micro", "crushing_strength_MPa", "micro.crushing_strength_pa", [](TestScheme& s) -> double& { return s.micro.crushing_strength_pa; }, 1e6, {.min = 0}, "Weibull characteristic crushing strength sigma0 (F/d^2) of a grain of the reference diameter; 0 = unbreakable grains"},
        {"micro", "crushing_reference_diameter_mm", "micro.crushing_reference_diameter_m", [](TestScheme& s) -> double& { return s.micro.crushing_reference_diameter_m; }, 1e-3, {.above = 0}, nullptr},
        {"micro", "crushing_weibull_modulus", "micro.crushing_weibull_modulus", [](TestScheme& s) -> double& { return s.micro.crushing_weibull_modulus; }, 1.0, {.min = 1, .max = 50}, nullptr},
        {"micro", "crushing_hardening_ratio", "micro.crushing_hardening_ratio", [](TestScheme& s) -> double& { return s.micro.crushing_hardening_ratio; }, 1.0, {.min = 0, .max = 10}, nullptr},
        {"creep", "direct_effect_a", "creep.direct_effect_a", [](TestScheme& s) -> double& { return s.creep.direct_effect_a; }, 1.0, {.min = 1e-4, .max = 0.1}, "a of rate-and-state friction at the contacts: slip rate v = (D_c / t_r) exp(-mu (1 - f) / a) (t_r / theta)^m, f = |Fs| / (mu Fn)"},
        {"creep", "critical_slip_um", "creep.critical_slip_m", [](TestScheme& s) -> double& { return s.creep.critical_slip_m; }, 1e-6, {.min = 0, .max = 1000}, "D_c of rate-and-state friction, micrometres: creep slip per e-fold of time at sliding; 0 = no contact creep"},
        {"creep", "renewed_age_s", "creep.renewed_age_s", [](TestScheme& s) -> double& { return s.creep.renewed_age_s; }, 1.0, {.min = 1e-3, .max = 86400}, "state theta of a contact renewed by its stage's loading step, seconds"},
        {"creep", "consolidated_age_s", "creep.consolidated_age_s", [](TestScheme& s) -> double& { return s.creep.consolidated_age_s; }, 1.0, {.min = 1, .max = 1e7}, "state theta of a contact formed in the preparation and consolidation, at the first stage's loading: the consolidation's hold, seconds"},
        {"creep", "state_exponent_m", "creep.state_exponent_m", [](TestScheme& s) -> double& { return s.creep.state_exponent_m; }, 1.0, {.min = 0.5, .max = 1}, "m = b / a of rate-and-state friction: under a held load the slip rate falls as t^-m (1 = creep logarithmic in time)"},
        {"creep", "bond_corrosion_rate_b1_per_s", "creep.bond_corrosion_rate_b1_per_s", [](TestScheme& s) -> double& { return s.creep.bond_corrosion_rate_b1_per_s; }, 1.0, {.min = 0}, "b1 of the bonds' stress corrosion dD/dt = b1 exp(b2 rho) above the threshold rho_th; 0 = no corrosion"},
        {"creep", "bond_corrosion_b2", "creep.bond_corrosion_b2", [](TestScheme& s) -> double& { return s.creep.bond_corrosion_b2; }, 1.0, {}, "b2 of the bonds' stress corrosion"},
        {"creep", "bond_corrosion_threshold", "creep.bond_corrosion_threshold", [](TestScheme& s) -> double& { return s.creep.bond_corrosion_threshold; }, 1.0, {}, "rho_th: load over strength above which a bond corrodes"},
        {"creep", "first_increment_s", "creep.first_increment_s", [](TestScheme& s) -> double& { return s.creep.first_increment_s; }, 1.0, {}, nullptr},
        {"creep", "increment_growth", "creep.increment_growth", [](TestScheme& s) -> double& { return s.creep.increment_growth; }, 1.0, {}, nullptr},
        {"creep", "max_increment_s", "creep.max_increment_s", [](TestScheme& s) -> double& { return s.creep.max_increment_s; }, 1.0, {}, nullptr},
        {"creep", "max_relaxation_per_increment", "creep.max_relaxation_per_increment", [](TestScheme& s) -> double& { return s.creep.max_relaxation_per_increment; }, 1.0, {.max = 1, .above = 0}, "an increment is split while it would relax more than this share of the contact shear force"},
        {"loading", "confining_pressure_kPa", "loading.confining_pressure_pa", [](TestScheme& s) -> double& { return s.loading.confining_pressure_pa; }, 1e3, {.above = 0, .below = 100000}, nullptr},
        {"loading", "cohesion_kPa", "loading.cohesion_pa", [](TestScheme& s) -> double& { return s.loading.cohesion_pa; }, 1e3, {}, nullptr},
        {"loading", "friction_angle_deg", "loading.friction_angle_deg", [](TestScheme& s) -> double& { return s.loading.friction_angle_deg; }, 1.0, {}, nullptr},
        {"loading", "max_axial_strain_pct", "loading.max_axial_strain", [](TestScheme& s) -> double& { return s.loading.max_axial_strain; }, 0.01, {}, nullptr},
        {"loading", "consolidation_tolerance", "loading.consolidation_tolerance", [](TestScheme& s) -> double& { return s.loading.consolidation_tolerance; }, 1.0, {}, nullptr},
        {"loading", "max_inertial_number", "loading.max_inertial_number", [](TestScheme& s) -> double& { return s.loading.max_inertial_number; }, 1.0, {.min = 1e-05, .max = 0.01}, "shear rate as the largest inertial number of the grains (quasi-static below about 1e-3)"},
        {"effects", "bond_corrosion_scale", "effects.bond_corrosion_scale", [](TestScheme& s) -> double& { return s.effects.bond_corrosion_scale; }, 1.0, {.min = 0}, "factor on creep.bond_corrosion_rate_b1_per_s when accelerated_bond_corrosion is on"},
        {"effects", "viscosity_scale", "effects.viscosity_scale", [](TestScheme& s) -> double& { return s.effects.viscosity_scale; }, 1.0, {}, nullptr},
        {"effects", "seating_displacement_mm", "effects.seating_displacement_m", [](TestScheme& s) -> double& { return s.effects.seating_displacement_m; }, 1e-3, {}, nullptr},
        {"effects", "membrane_modulus_kPa", "effects.membrane_modulus_pa", [](TestScheme& s) -> double& { return s.effects.membrane_modulus_pa; }, 1e3, {}, nullptr},
        {"effects", "membrane_thickness_mm", "effects.membrane_thickness_m", [](TestScheme& s) -> double& { return s.effects.membrane_thickness_m; }, 1e-3, {}, nullptr},
    };
    return f;
}

const std::vector<BoolField>& bool_fields() {
    static const std::vector<BoolField> f = {
        {"effects", "accelerated_bond_corrosion", [](TestScheme& s) -> bool& { return s.effects.accelerated_bond_corrosion; }, "bond degradation: the bonds corrode bond_corrosion_scale times faster"},
        {"effects", "contact_creep_viscosity", [](TestScheme& s) -> bool& { return s.effects.contact_creep_viscosity; }, nullptr},
        {"effects", "moisture_bonding", [](TestScheme& s) -> bool& { return s.effects.moisture_bonding; }, nullptr},
        {"effects", "seating_error", [](TestScheme& s) -> bool& { return s.effects.seating_error; }, nullptr},
        {"effects", "membrane_compliance", [](TestScheme& s) -> bool& { return s.effects.membrane_compliance; }, nullptr},
        {"micro", "crushing_breaks_bond", [](TestScheme& s) -> bool& { return s.micro.crushing_breaks_bond; }, nullptr},
        {"loading", "stop_at_softening", [](TestScheme& s) -> bool& { return s.loading.stop_at_softening; }, "end the shear at strain softening (q 20 % below its peak past 2 % strain); false runs to max_axial_strain_pct"},
    };
    return f;
}

const std::vector<ShapedField>& shaped_fields() {
    static const std::vector<ShapedField> f = [] {
        ordered_json groups = ordered_json::array();
        for (const auto& g : protocol::paper_groups()) groups.push_back(g.name);
        return std::vector<ShapedField>{
            {"", "name", {{"type", "string"}}},
            {"", "preset",
             {{"type", "string"},
              {"enum", groups},
              {"description", "start from this paper group (Table 2 with the presets' micro-parameters, GET /presets); "
                              "the other fields change only what they name"}}},
            {"", "seed", {{"type", "integer"}, {"minimum", 0}}},
            {"", "threads", {{"type", "integer"}, {"minimum", 1}, {"maximum", 256}}},
            {"", "max_particles",
             {{"type", "integer"},
              {"minimum", 0},
              {"description", "0 = the gradation decides; otherwise radii are scaled up until the soil count fits "
                              "(reduced specimens)"}}},
            {"specimen", "lateral_boundary",
             {{"enum", {"bonded_membrane", "grain_pressure"}},
              {"description", "how sigma3 reaches the soil: the paper's bonded-sphere membrane, or the pressure on the "
                              "outermost grains with no membrane (no lattice confinement; the diagnosis's base)"}}},
            {"gradation", "kind", {{"enum", {"radius_ratio", "sieve_curve"}}}},
            {"gradation", "sieve_curve",
             {{"type", "array"},
              {"items",
               {{"type", "object"},
                {"required", {"size_mm", "passing_pct"}},
                {"additionalProperties", false},
                {"properties",
                 {{"size_mm", {{"type", "number"}, {"exclusiveMinimum", 0}}},
                  {"passing_pct", {{"type", "number"}, {"minimum", 0}, {"maximum", 100}}}}}}}}},
            {"loading", "stress_levels",
             {{"type", "array"}, {"items", {{"type", "number"}, {"exclusiveMinimum", 0}, {"exclusiveMaximum", 1.5}}}}},
            {"loading", "stage_durations_min", {{"type", "array"}, {"items", {{"type", "number"}, {"exclusiveMinimum", 0}}}}},
            {"loading", "stress_level_definition", {{"enum", {"q_over_qf", "eq1"}}}},
        };
    }();
    return f;
}

const std::vector<RetiredField>& retired_fields() {
    // The lab strain rate: ignored, the engine shears at the quasi-static rate of
    // loading.max_inertial_number (engine/protocol/triaxial_shear.hpp).
    // The rolling-resistance switch and its value: read as micro.rolling_friction (the one
    // rolling setting) when the switch is on (scheme_json.cpp).
    static const std::vector<RetiredField> f = {
        {"loading", "shear_strain_rate_pct_per_min"},
        {"effects", "rolling_resistance"},
        {"effects", "rolling_friction"},
    };
    return f;
}

}  // namespace triax::io
