#include "engine/protocol/creep_stage.hpp"

#include <algorithm>
#include <string>

#include "engine/creep/coordinate_translation.hpp"
#include "engine/creep/time_schedule.hpp"
#include "engine/protocol/creep_regime.hpp"
#include "engine/protocol/stress_level.hpp"

namespace triax::protocol {

creep::RateStateParams effective_creep_law(const TestScheme& scheme) {
    creep::RateStateParams cp = scheme.creep;
    const double vs = scheme.effects.contact_creep_viscosity ? scheme.effects.viscosity_scale : 0.0;
    cp.critical_slip_m = scheme.creep.critical_slip_m * vs;
    cp.bond_corrosion_rate_b1_per_s =
        scheme.creep.bond_corrosion_rate_b1_per_s * vs *
        (scheme.effects.accelerated_bond_corrosion ? scheme.effects.bond_corrosion_scale : 1.0);
    return cp;
}

MultiStageCreep::MultiStageCreep(Specimen& sp, const PlatenServo& servo, double q_failure_pa, RunContext& run)
    : sp_(sp),
      w_(sp.world()),
      run_(run),
      sigma3_(run.scheme.loading.confining_pressure_pa),
      q_failure_(q_failure_pa),
      eps_max_(run.scheme.loading.max_axial_strain),
      law_(effective_creep_law(run.scheme), kSoilGroup),
      // Creep readings are deformations at a held stress and in equilibrium (creep_hold.hpp).
      holder_(sp, sigma3_, servo, run.scheme.loading.consolidation_tolerance),
      rotation_(sp.soil_count(), Vec3::Zero()),
      hc_(sp.height()),
      z_top0_(sp.top_z()) {
    // Measurement spheres on the axis at z = +0.4 H, 0, -0.4 H (specimen_snapshot.hpp, one
    // layout for the stage and the snapshots).
    for (const auto& m : measurement_sphere_layout(run.scheme, sp.mean_diameter())) spheres_.emplace_back(m.center, m.radius_m);
    run.result.measurement_sphere_radius_m = spheres_.front().radius();
    for (auto& m : spheres_) m.set_reference(w_);
}

void MultiStageCreep::sample_spheres(double t) {
    const double span = t - last_sample_t_;
    for (int s = 0; s < 3; ++s) {
        const auto r = spheres_[s].measure(w_);
        Vec3 rot = Vec3::Zero();
        int inside = 0;
        for (int i = 0; i < sp_.soil_count(); ++i)
            if ((w_.particles().position[i] - spheres_[s].center()).norm() <= spheres_[s].radius()) {
                rot += rotation_[i];
                ++inside;
            }
        const Vec3 rate = (inside > 0 && span > 0.0) ? Vec3(rot / (inside * span)) : Vec3(Vec3::Zero());
        MeasurementSample ms;
        ms.sphere = s + 1;
        ms.step = w_.step();
        ms.time_s = t;
        ms.z_displacement_m = r.mean_displacement.z();
        ms.rotation_rate_x_rad_s = rate.x();
        ms.rotation_rate_y_rad_s = rate.y();
        ms.rotation_rate_z_rad_s = rate.z();
        ms.porosity = r.porosity;
        ms.coordination = r.coordination;
        run_.result.measurements.push_back(ms);
        run_.observer.measurement_sample(ms);
    }
    for (auto& r : rotation_) r.setZero();
    last_sample_t_ = t;
}

CreepStageResult MultiStageCreep::run_stage(int k, double q_target) {
    const TestScheme& scheme = run_.scheme;
    TestResult& res = run_.result;
    const double sigma1 = sigma3_ + q_target;
    const std::string stage = "creep-" + std::to_string(k + 1);
    CreepStageResult st;
    st.stage = k + 1;
    st.q_pa = q_target;
    st.stress_level = q_failure_ > 0.0 ? q_target / q_failure_ : 0.0;
    st.stress_level_eq1 = stress_level_eq1(q_target, sigma3_, scheme.loading.cohesion_pa, scheme.loading.friction_angle_deg);
    st.duration_s = scheme.loading.stage_durations_s[k];
    st.start_time_s = t_total_;
    const double d_before = z_top0_ - sp_.top_z();
    // The contacts' shear forces before the load: the loading's displacement renews their
    // state (creep counts from the load step); then the loading step: the instant response.
    law_.begin_stage(w_, k == 0);
    holder_.hold(sigma1, 500, 200000, &rotation_);
    auto record = [&](double t_stage) {
        const double d = z_top0_ - sp_.top_z();
        CreepPoint cpnt{t_total_ + t_stage, d, d / hc_};
        st.raw.push_back(cpnt);
        run_.observer.creep_point(k + 1, cpnt);
        const auto es = energy_sample(w_, 2 + k, t_total_ + t_stage);
        res.energies.push_back(es);
        run_.observer.energy_sample(es);
    };
    record(0.0);
    sample_spheres(t_total_);
    const double d_loading = z_top0_ - sp_.top_z() - d_before;
    const auto dts = creep::creep_time_increments(st.duration_s, scheme.creep.first_increment_s,
                                                  scheme.creep.increment_growth, scheme.creep.max_increment_s);
    double t = 0.0;
    for (std::size_t n = 0; n < dts.size(); ++n) {
        const double d_increment_start = z_top0_ - sp_.top_z();
        // Split the increment while it would relax too much shear force at once: the
        // mechanical relaxation then follows the creep (increment convergence).
        double left = dts[n];
        while (left > 0.0) {
            double h = left;
            for (int halving = 0;
                 halving < 8 && law_.trial(w_, h).relaxation > scheme.creep.max_relaxation_per_increment; ++halving)
                h *= 0.5;
            law_.advance(w_, h);
            const long crushed_before = sp_.crushing_events();
            const long cycles = holder_.hold(sigma1, 100, 20000, &rotation_);
            ++res.creep_relaxations;
            left = h < left ? left - h : 0.0;
            CreepIncrementLog il;
            il.stage = k + 1;
            il.t_stage_s = t + (dts[n] - left);
            il.dt_s = h;
            il.hold_cycles = cycles;
            il.crushing_events = sp_.crushing_events() - crushed_before;
            il.deformation_m = z_top0_ - sp_.top_z();
            run_.observer.creep_increment(il);
            // A collapse is read piece by piece: driven on, its relaxations run at their
            // cycle cap, piece after piece, until the specimen finds a new equilibrium
            // several per cent of strain later.
            if (creep_collapse(il.deformation_m - d_increment_start, d_loading)) {
                st.ruptured = true;
                break;
            }
        }
        t += dts[n] - left;
        record(t);
        if (n % 4 == 3 || n + 1 == dts.size()) sample_spheres(t_total_ + t);
        run_.progress.report(stage, 2 + k, t / st.duration_s);
        // Creep rupture: the platen runs away beyond the shear test's range (or the
        // specimen collapsed within the increment, above).
        if ((z_top0_ - sp_.top_z()) / hc_ > std::max(0.25, eps_max_ + 0.05)) st.ruptured = true;
        if (st.ruptured) {
            st.rupture_time_s = t;
            break;
        }
    }
    // Per-stage curves and summary numbers.
    std::vector<creep::TimeDeformation> stage_raw;
    for (const auto& p : st.raw) stage_raw.push_back({p.time_s, p.axial_deformation_m});
    std::vector<creep::TimeDeformation> tr = creep::translate_stage(stage_raw, st.start_time_s, st.start_time_s + t, d_before);
    for (const auto& p : tr) st.translated.push_back({p.time, p.deformation, p.deformation / hc_});
    st.instant_deformation_m = st.translated.front().axial_deformation_m;
    st.final_deformation_m = st.translated.back().axial_deformation_m;
    const double creep_part = st.final_deformation_m - st.instant_deformation_m;
    st.elastic_share = st.final_deformation_m > 0.0 ? st.instant_deformation_m / st.final_deformation_m : 1.0;
    const double d30 = deformation_at(st, 1800.0);
    st.share_in_first_30min = creep_part > 0.0 ? std::clamp((d30 - st.instant_deformation_m) / creep_part, 0.0, 1.0) : 1.0;
    st.total_share_in_first_30min = st.final_deformation_m > 0.0 ? std::clamp(d30 / st.final_deformation_m, 0.0, 1.0) : 1.0;
    const CreepRegime regime = classify_creep_regime(st, t);
    st.accelerating = regime.accelerating;
    st.converged = regime.converged;
    t_total_ += t;
    return st;
}

}  // namespace triax::protocol
