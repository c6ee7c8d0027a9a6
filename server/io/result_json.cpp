#include "server/io/result_json.hpp"

#include <stdexcept>

namespace triax::io {

using nlohmann::json;
using namespace triax::protocol;

namespace {
constexpr double kPa = 1e-3, kPct = 100.0, kMm = 1e3, kMin = 1.0 / 60.0;
}

json result_summary_to_json(const TestResult& r) {
    json stages = json::array();
    for (const auto& s : r.creep_stages) {
        stages.push_back({{"stage", s.stage},
                          {"stress_level", s.stress_level},
                          {"stress_level_eq1", s.stress_level_eq1},
                          {"q_kPa", s.q_pa * kPa},
                          {"duration_min", s.duration_s * kMin},
                          {"start_time_min", s.start_time_s * kMin},
                          {"instant_deformation_mm", s.instant_deformation_m * kMm},
                          {"final_deformation_mm", s.final_deformation_m * kMm},
                          {"elastic_share_pct", s.elastic_share * kPct},
                          {"share_in_first_30min_pct", s.share_in_first_30min * kPct},
                          {"total_share_in_first_30min_pct", s.total_share_in_first_30min * kPct},
                          {"converged", s.converged},
                          {"accelerating", s.accelerating},
                          {"ruptured", s.ruptured},
                          {"rupture_time_min", s.ruptured ? json(s.rupture_time_s * kMin) : json()}});
    }
    return {{"scheme_name", r.scheme_name},
            {"sigma3_kPa", r.sigma3_pa * kPa},
            {"q_failure_kPa", r.q_failure_pa * kPa},
            {"axial_strain_at_failure_pct", r.axial_strain_at_failure * kPct},
            {"particle_count", r.particle_count},
            {"membrane_particle_count", r.membrane_particle_count},
            {"initial_porosity", r.initial_porosity},
            {"max_inertial_number", r.max_inertial_number},
            // The density I was computed with (density-scaled grains, docs/protocol.md):
            // without it the inertial number cannot be checked or compared across runs.
            {"inertial_density_kg_m3", r.inertial_density_kg_m3},
            {"measurement_sphere_radius_mm", r.measurement_sphere_radius_m * kMm},
            {"consolidation",
             {{"unbalanced_force_ratio", r.consolidation.unbalanced_force_ratio},
              {"porosity", r.consolidation.porosity},
              {"steps", r.consolidation.steps},
              {"achieved_sigma3_kPa", r.consolidation.achieved_sigma3_pa * kPa}}},
            {"creep_stages", stages},
            {"converged", r.converged},
            {"cancelled", r.cancelled},
            {"wall_time_s", r.wall_time_s},
            {"total_steps", r.total_steps}};
}

json result_series_to_json(const TestResult& r, const std::string& series) {
    json rows = json::array();
    json columns;
    if (series == "stress_strain") {
        columns = {"axial_strain_pct", "q_kPa", "p_kPa", "sigma1_kPa", "sigma3_kPa"};
        for (const auto& p : r.shear)
            rows.push_back({p.axial_strain * kPct, p.q_pa * kPa, p.p_pa * kPa, p.sigma1_pa * kPa, p.sigma3_pa * kPa});
    } else if (series == "volumetric") {
        columns = {"axial_strain_pct", "volumetric_strain_pct"};
        for (const auto& p : r.shear) rows.push_back({p.axial_strain * kPct, p.volumetric_strain * kPct});
    } else if (series == "creep" || series == "creep_raw") {
        columns = {"stage", "time_min", "axial_deformation_mm", "axial_strain_pct"};
        for (const auto& s : r.creep_stages)
            for (const auto& p : (series == "creep" ? s.translated : s.raw))
                rows.push_back({s.stage, p.time_s * kMin, p.axial_deformation_m * kMm, p.axial_strain * kPct});
    } else if (series == "energies") {
        columns = {"phase_index", "step", "time_min", "strain_J", "slip_J", "damping_J", "kinetic_J", "bond_J",
                   "boundary_work_J", "creep_J", "breakage_J"};
        for (const auto& e : r.energies)
            rows.push_back({e.phase_index, e.step, e.time_s * kMin, e.strain_j, e.slip_j, e.damping_j, e.kinetic_j,
                            e.bond_j, e.boundary_work_j, e.creep_j, e.breakage_j});
    } else if (series == "measurements") {
        columns = {"sphere", "step", "time_min", "z_displacement_mm", "rotation_rate_x_rad_s", "rotation_rate_y_rad_s",
                   "rotation_rate_z_rad_s", "porosity", "coordination"};
        for (const auto& m : r.measurements)
            rows.push_back({m.sphere, m.step, m.time_s * kMin, m.z_displacement_m * kMm, m.rotation_rate_x_rad_s,
                            m.rotation_rate_y_rad_s, m.rotation_rate_z_rad_s, m.porosity, m.coordination});
    } else {
        throw std::invalid_argument("unknown series '" + series +
                                    "' (valid: stress_strain, volumetric, creep, creep_raw, energies, measurements)");
    }
    return {{"series", series}, {"columns", columns}, {"rows", rows}};
}

json result_to_json(const TestResult& r) {
    json series = json::object();
    for (const char* s : {"stress_strain", "volumetric", "creep", "creep_raw", "energies", "measurements"})
        series[s] = result_series_to_json(r, s);
    return {{"summary", result_summary_to_json(r)}, {"series", series}};
}

json shear_point_to_json(const ShearPoint& p) {
    return {{"axial_strain_pct", p.axial_strain * kPct}, {"q_kPa", p.q_pa * kPa},
            {"volumetric_strain_pct", p.volumetric_strain * kPct}, {"p_kPa", p.p_pa * kPa}};
}

json creep_point_to_json(int stage, const CreepPoint& p) {
    return {{"stage", stage}, {"time_min", p.time_s * kMin}, {"axial_deformation_mm", p.axial_deformation_m * kMm},
            {"axial_strain_pct", p.axial_strain * kPct}};
}

json energy_sample_to_json(const EnergySample& e) {
    static const char* phases[] = {"consolidation", "shear"};
    const std::string phase = e.phase_index < 2 ? phases[e.phase_index] : "creep-" + std::to_string(e.phase_index - 1);
    return {{"phase", phase}, {"phase_index", e.phase_index}, {"step", e.step}, {"time_min", e.time_s * kMin},
            {"strain_J", e.strain_j}, {"slip_J", e.slip_j}, {"damping_J", e.damping_j}, {"kinetic_J", e.kinetic_j},
            {"bond_J", e.bond_j}, {"boundary_work_J", e.boundary_work_j}, {"creep_J", e.creep_j},
            {"breakage_J", e.breakage_j}};
}

json measurement_sample_to_json(const MeasurementSample& m) {
    return {{"sphere", m.sphere}, {"step", m.step}, {"time_min", m.time_s * kMin},
            {"z_displacement_mm", m.z_displacement_m * kMm}, {"rotation_rate_x_rad_s", m.rotation_rate_x_rad_s},
            {"rotation_rate_y_rad_s", m.rotation_rate_y_rad_s}, {"rotation_rate_z_rad_s", m.rotation_rate_z_rad_s},
            {"porosity", m.porosity}, {"coordination", m.coordination}};
}

}  // namespace triax::io
