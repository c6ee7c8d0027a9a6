#include "server/runs/engine_executor.hpp"
#include "server/runs/series.hpp"

#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/scheme_json.hpp"

#include <chrono>

namespace triax::service {

using nlohmann::json;

namespace {

constexpr double kPa = 1e-3, pct = 100.0, mm = 1e3, minutes = 1.0 / 60.0;

json shear_json(const protocol::ShearPoint& p) {
    return {{"axial_strain_pct", p.axial_strain * pct}, {"q_kPa", p.q_pa * kPa},
            {"p_kPa", p.p_pa * kPa},                    {"sigma1_kPa", p.sigma1_pa * kPa},
            {"sigma3_kPa", p.sigma3_pa * kPa},          {"volumetric_strain_pct", p.volumetric_strain * pct},
            {"inertial_number", p.inertial_number}};
}

json creep_json(int stage, const protocol::CreepPoint& p) {
    return {{"stage", stage},
            {"time_min", p.time_s * minutes},
            {"axial_deformation_mm", p.axial_deformation_m * mm},
            {"axial_strain_pct", p.axial_strain * pct}};
}

const char* phase_name(int phase_index) {
    return phase_index == 0 ? "consolidation" : phase_index == 1 ? "shear" : "creep";
}

json energy_json(const protocol::EnergySample& e) {
    return {{"phase", phase_name(e.phase_index)}, {"phase_index", e.phase_index}, {"step", e.step},
            {"time_min", e.time_s * minutes},     {"strain_J", e.strain_j},       {"slip_J", e.slip_j},
            {"damping_J", e.damping_j},           {"kinetic_J", e.kinetic_j},     {"bond_J", e.bond_j},
            {"boundary_work_J", e.boundary_work_j}, {"creep_J", e.creep_j}};
}

json measurement_json(const protocol::MeasurementSample& m) {
    return {{"sphere", m.sphere},
            {"step", m.step},
            {"time_min", m.time_s * minutes},
            {"z_displacement_mm", m.z_displacement_m * mm},
            {"rotation_rate_x_rad_s", m.rotation_rate_x_rad_s},
            {"rotation_rate_y_rad_s", m.rotation_rate_y_rad_s},
            {"rotation_rate_z_rad_s", m.rotation_rate_z_rad_s},
            {"porosity", m.porosity},
            {"coordination", m.coordination}};
}

// Streams what the engine reports. Progress is thinned to a few events per second: the
// engine may report every increment and each event is a database row.
class StreamingObserver : public protocol::RunObserver {
public:
    explicit StreamingObserver(RunContext& ctx) : ctx_(ctx) {}
    void progress(const std::string& stage, double fraction, double eta_s) override {
        const auto now = std::chrono::steady_clock::now();
        if (stage == last_stage_ && now - last_progress_ < std::chrono::milliseconds(250) && fraction < 1.0) return;
        last_progress_ = now;
        last_stage_ = stage;
        json d{{"stage", stage}, {"progress_pct", 100.0 * fraction}};
        d["eta_s"] = eta_s >= 0 ? json(eta_s) : json(nullptr);
        ctx_.emit("progress", d);
    }
    void stage_changed(const std::string& stage, int index, double stress_level, double q_target_pa) override {
        json d{{"stage", stage}, {"index", index}};
        if (index > 0) {
            d["stress_level"] = stress_level;
            d["q_target_kPa"] = q_target_pa * kPa;
        }
        ctx_.emit("stage", d);
    }
    void shear_point(const protocol::ShearPoint& p) override { ctx_.emit("shear", shear_json(p)); }
    void creep_point(int stage, const protocol::CreepPoint& p) override { ctx_.emit("creep", creep_json(stage, p)); }
    void energy_sample(const protocol::EnergySample& e) override { ctx_.emit("energy", energy_json(e)); }
    void measurement_sample(const protocol::MeasurementSample& m) override {
        ctx_.emit("measurement", measurement_json(m));
    }
    bool cancel_requested() override { return ctx_.cancel_requested(); }

private:
    RunContext& ctx_;
    std::string last_stage_;
    std::chrono::steady_clock::time_point last_progress_{};
};

}  // namespace

json result_document(const protocol::TestResult& r) {
    json stages = json::array();
    json creep_rows = json::array();
    for (const auto& s : r.creep_stages) {
        stages.push_back({{"stage", s.stage},
                          {"stress_level", s.stress_level},
                          {"stress_level_eq1", s.stress_level_eq1},
                          {"q_kPa", s.q_pa * kPa},
                          {"duration_min", s.duration_s * minutes},
                          {"start_time_min", s.start_time_s * minutes},
                          {"instant_deformation_mm", s.instant_deformation_m * mm},
                          {"final_deformation_mm", s.final_deformation_m * mm},
                          {"share_in_first_30min_pct", s.share_in_first_30min * pct},
                          {"elastic_share_pct", s.elastic_share * pct},
                          {"converged", s.converged},
                          {"accelerating", s.accelerating}});
        // The per-stage curve in the paper's translated coordinates (time and deformation
        // from the stage start, Boltzmann superposition).
        for (const auto& p : s.translated) {
            const auto j = creep_json(s.stage, p);
            creep_rows.push_back({j["stage"], j["time_min"], j["axial_deformation_mm"], j["axial_strain_pct"]});
        }
    }
    json summary{{"scheme_name", r.scheme_name},
                 {"sigma3_kPa", r.sigma3_pa * kPa},
                 {"q_failure_kPa", r.q_failure_pa * kPa},
                 {"axial_strain_at_failure_pct", r.axial_strain_at_failure * pct},
                 {"particle_count", r.particle_count},
                 {"membrane_particle_count", r.membrane_particle_count},
                 {"initial_porosity", r.initial_porosity},
                 {"max_inertial_number", r.max_inertial_number},
                 {"consolidation",
                  {{"unbalanced_force_ratio", r.consolidation.unbalanced_force_ratio},
                   {"porosity", r.consolidation.porosity},
                   {"steps", r.consolidation.steps},
                   {"achieved_sigma3_kPa", r.consolidation.achieved_sigma3_pa * kPa}}},
                 {"creep_stages", stages},
                 {"measurement_sphere_radius_mm", r.measurement_sphere_radius_m * mm},
                 {"converged", r.converged},
                 {"cancelled", r.cancelled},
                 {"wall_time_s", r.wall_time_s},
                 {"total_steps", r.total_steps}};
    auto rows_of = [](const char* name, const std::vector<json>& objects) {
        return rows_from_events(*find_series(name), objects);
    };
    std::vector<json> shear, energies, measurements;
    for (const auto& p : r.shear) shear.push_back(shear_json(p));
    for (const auto& e : r.energies) energies.push_back(energy_json(e));
    for (const auto& m : r.measurements) measurements.push_back(measurement_json(m));
    json series{{"stress_strain", rows_of("stress_strain", shear)},
                {"volumetric", rows_of("volumetric", shear)},
                {"creep", creep_rows},
                {"energies", rows_of("energies", energies)},
                {"measurements", rows_of("measurements", measurements)}};
    return {{"summary", summary}, {"series", series}};
}

RunExecutor make_engine_executor() {
    return [](const json& scheme_json, RunContext& ctx) -> json {
        auto scheme = io::scheme_from_json(scheme_json);
        scheme.threads = ctx.threads;
        StreamingObserver observer(ctx);
        const auto result = protocol::run_triaxial_test(scheme, observer);
        if (result.cancelled) throw RunCancelled();
        return result_document(result);
    };
}

}  // namespace triax::service
