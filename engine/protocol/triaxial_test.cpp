#include "engine/protocol/triaxial_test.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "engine/creep/coordinate_translation.hpp"
#include "engine/creep/rate_process_creep.hpp"
#include "engine/creep/time_schedule.hpp"
#include "engine/measure/measurement_sphere.hpp"
#include "engine/protocol/creep_hold.hpp"
#include "engine/protocol/creep_regime.hpp"
#include "engine/protocol/specimen.hpp"
#include "engine/protocol/stress_level.hpp"

namespace triax::protocol {

namespace {

constexpr long kChunk = 50;                 // cycles between servo / record updates
constexpr double kStressTolerance = 0.01;   // relative, servo targets

// The run's clock and the progress line: weights per phase of the whole run.
class Progress {
public:
    Progress(RunObserver& o, int creep_stages) : obs_(o), start_(std::chrono::steady_clock::now()) {
        const double creep_w = creep_stages > 0 ? 0.55 / creep_stages : 0.0;
        weights_ = {0.1, 0.1, 0.25};
        for (int k = 0; k < creep_stages; ++k) weights_.push_back(creep_w);
    }
    void report(const std::string& stage, int phase, double fraction) {
        double done = 0.0;
        for (int k = 0; k < phase && k < static_cast<int>(weights_.size()); ++k) done += weights_[k];
        done += weights_[std::min<int>(phase, weights_.size() - 1)] * std::clamp(fraction, 0.0, 1.0);
        double total = 0.0;
        for (double w : weights_) total += w;
        const double f = done / total;
        const double el = elapsed();
        obs_.progress(stage, f, f > 0.02 ? el * (1.0 - f) / f : -1.0);
        if (obs_.cancel_requested()) throw Cancelled{};
    }
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    struct Cancelled {};

private:
    RunObserver& obs_;
    std::chrono::steady_clock::time_point start_;
    std::vector<double> weights_;
};

// Servo on a platen (PFC-style): wall speed proportional to the stress error, gain from
// the skeleton stiffness so that one chunk closes a fraction of the error.
double servo_velocity(double target, double measured, double area, double k_skeleton, double dt, double v_max) {
    const double gain = 0.2 * area / (k_skeleton * dt * kChunk);
    return std::clamp(gain * (target - measured), -v_max, v_max);
}

EnergySample energy_sample(const World& w, int phase, double time_s) {
    const auto& e = w.energy();
    EnergySample s;
    s.phase_index = phase;
    s.step = w.step();
    s.time_s = time_s;
    s.strain_j = e.strain;
    s.slip_j = e.slip;
    s.damping_j = e.damping;
    s.kinetic_j = e.kinetic;
    s.bond_j = e.bond_strain;
    s.boundary_work_j = e.boundary_work;
    s.creep_j = e.creep;
    s.breakage_j = e.breakage;
    return s;
}

}  // namespace

TestResult run_triaxial_test(const TestScheme& scheme) {
    RunObserver none;
    return run_triaxial_test(scheme, none);
}

TestResult run_triaxial_test(const TestScheme& scheme, RunObserver& obs, Phase last) {
    return run_triaxial_test(scheme, obs, last, HoldOptions{});
}

TestResult run_triaxial_test(const TestScheme& scheme, RunObserver& obs, Phase last, const HoldOptions& hold_options) {
    scheme.validate();
    TestResult res;
    res.scheme_name = scheme.name;
    const int n_stages = last == Phase::Creep ? static_cast<int>(scheme.loading.stress_levels.size()) : 0;
    Progress prog(obs, n_stages);
    const double sigma3 = scheme.loading.confining_pressure_pa;
    res.sigma3_pa = sigma3;
    try {
        // ---- generation and isotropic consolidation ------------------------------
        // The creep test runs on a second specimen built identically (same seed): the
        // lab's q_f comes from a companion shear test, the graded creep loading starts
        // from the isotropic state (paper, "Scheme of Creep Test").
        auto consolidated = [&](bool report) {
            obs.stage_changed("generation", 0, 0.0, 0.0);
            prog.report("generation", 0, 0.0);
            auto sp = std::make_unique<Specimen>(scheme);
            World& w = sp->world();
            if (report) {
                res.particle_count = sp->soil_count();
                res.membrane_particle_count = sp->membrane().count();
                res.initial_porosity = sp->porosity();
            }
            sp->install_test_laws();
            sp->membrane().set_fixed(w, false);
            const double dt = w.time_step();
            const double k_skel = sp->soil_kn() * 8.0;  // about 8 contacts under a grain
            const double v_max = 0.05 * sp->height() / (2000.0 * dt);
            obs.stage_changed("consolidation", 0, 0.0, 0.0);
            w.energy().reset_accumulated();
            const long consolidation_start = w.step();
            double ratio = 1.0;
            const long max_consolidation = 400000;
            for (long n = 0; n < max_consolidation; n += kChunk) {
                const double area = sp->volume() / sp->height();
                auto& top = w.plane_wall(sp->top_wall());
                auto& bot = w.plane_wall(sp->bottom_wall());
                top.velocity = Vec3(0, 0, -servo_velocity(sigma3, top.normal_stress(area), area, k_skel, dt, v_max));
                bot.velocity = Vec3(0, 0, servo_velocity(sigma3, bot.normal_stress(area), area, k_skel, dt, v_max));
                sp->cycle(kChunk, sigma3);
                ratio = w.unbalanced_force_ratio();
                const bool stress_ok = std::abs(sp->axial_stress() - sigma3) < kStressTolerance * sigma3;
                if (n > 2000 && stress_ok && ratio < scheme.loading.consolidation_tolerance) break;
                if (n % 2000 == 0) prog.report("consolidation", 0, std::min(1.0, 0.5 * n / 20000.0));
            }
            w.plane_wall(sp->top_wall()).velocity.setZero();
            w.plane_wall(sp->bottom_wall()).velocity.setZero();
            if (report) {
                res.consolidation.unbalanced_force_ratio = ratio;
                res.consolidation.porosity = sp->porosity();
                res.consolidation.steps = w.step() - consolidation_start;
                res.consolidation.achieved_sigma3_pa = sp->axial_stress();
                obs.energy_sample(energy_sample(w, 0, 0.0));
                res.energies.push_back(energy_sample(w, 0, 0.0));
            }
            // Bonds (suction/cementation, moisture dependent) form on the consolidated fabric.
            sp->install_soil_bonds();
            sp->enable_crushing();
            return sp;
        };
        auto shear_specimen = consolidated(true);
        // The creep specimen is the same consolidated specimen (same seed, deterministic
        // engine): a copy saves generating and consolidating it a second time.
        auto creep_copy = n_stages > 0 && last == Phase::Creep ? std::make_unique<Specimen>(*shear_specimen) : nullptr;
        Specimen* spp = shear_specimen.get();
        World* wp = &spp->world();
        const double dt = wp->time_step();
        const double k_skel = spp->soil_kn() * 8.0;
        const double v_max = 0.05 * spp->height() / (2000.0 * dt);

        // ---- strain-controlled shear ------------------------------------------
        obs.stage_changed("shear", 0, 0.0, 0.0);
        double q_peak = 0.0, eps_peak = 0.0;
        double shear_speed = 0.0;  // m/s, the quasi-static platen speed of the shear test
        const double eps_max = scheme.loading.max_axial_strain;
        {
        Specimen& sp = *spp;
        World& w = *wp;
        const double h0 = sp.height(), v0 = sp.volume();
        const double p0 = std::max(sigma3, 1.0);
        // Density scaling raises the inertial mass of the grains (World::set_density_scaling);
        // the inertial number that tells whether the shear is quasi-static is the one of the
        // scaled grains, so the rate is chosen from the scaled density, not the true one.
        double m_true = 0.0, m_inertial = 0.0;
        for (int i = 0; i < sp.soil_count(); ++i) {
            m_true += w.particles().mass[i];
            m_inertial += std::max(w.particles().mass[i], w.inertial_masses()[i]);
        }
        const double rho_inertial = sp.soil_density() * m_inertial / m_true;
        res.inertial_density_kg_m3 = rho_inertial;
        const double rate = scheme.loading.max_inertial_number * std::sqrt(p0 / rho_inertial) / sp.mean_diameter();
        const double seating = scheme.effects.seating_error ? scheme.effects.seating_displacement_m : 0.0;
        shear_speed = rate * h0;
        w.plane_wall(sp.top_wall()).velocity = Vec3(0, 0, -rate * h0);
        const long record_every = std::max<long>(kChunk, static_cast<long>(0.002 / (rate * dt)) / kChunk * kChunk);
        long since_record = 0;
        while (true) {
            sp.cycle(kChunk, sigma3);
            since_record += kChunk;
            const double eps_a = (h0 - sp.height()) / h0;
            if (since_record >= record_every || eps_a >= eps_max) {
                since_record = 0;
                ShearPoint pt;
                // Seating (bedding) error: the lab's displacement reading includes the
                // closing of the platen-specimen gap before the specimen carries load.
                pt.axial_strain = eps_a + seating / h0;
                const double sigma1 = sp.top_stress();
                double q = sigma1 - sigma3;
                if (scheme.effects.membrane_compliance) {
                    // Uncorrected hoop-tension of a real membrane adds to the measured q
                    // (ASTM D7181 form): dq = 4 E_m t_m eps_a / D.
                    q += 4.0 * scheme.effects.membrane_modulus_pa * scheme.effects.membrane_thickness_m * eps_a /
                         scheme.specimen.diameter_m;
                }
                pt.q_pa = q;
                pt.sigma1_pa = sigma3 + q;
                pt.sigma3_pa = sigma3;
                pt.p_pa = sigma3 + q / 3.0;
                pt.volumetric_strain = (v0 - sp.volume()) / v0;
                pt.inertial_number = rate * sp.mean_diameter() * std::sqrt(rho_inertial / std::max(pt.p_pa, 1.0));
                res.max_inertial_number = std::max(res.max_inertial_number, pt.inertial_number);
                res.shear.push_back(pt);
                obs.shear_point(pt);
                const auto es = energy_sample(w, 1, 0.0);
                res.energies.push_back(es);
                obs.energy_sample(es);
                if (q > q_peak) { q_peak = q; eps_peak = pt.axial_strain; }
                prog.report("shear", 1, eps_a / eps_max);
            }
            if (eps_a >= eps_max) break;
            // Failure: a clear peak, then a 20 % drop (strain softening) ends the shear.
            if (scheme.loading.stop_at_softening && q_peak > 0.0 && !res.shear.empty() && res.shear.back().q_pa < 0.8 * q_peak && eps_a > 0.02) break;
        }
        w.plane_wall(sp.top_wall()).velocity.setZero();
        }
        res.q_failure_pa = q_peak;
        res.axial_strain_at_failure = eps_peak;
        if (last == Phase::Shear || last == Phase::Consolidation || n_stages == 0) {
            res.total_steps = wp->step();
            res.wall_time_s = prog.elapsed();
            obs.stage_changed("done", 0, 0.0, 0.0);
            return res;
        }
        // Steps done on the shear specimen after the copy (the copy's history counts once).
        const long shear_steps = wp->step() - creep_copy->world().step();
        shear_specimen.reset();
        auto creep_specimen = std::move(creep_copy);
        Specimen& sp = *creep_specimen;
        World& w = sp.world();
        // Grain rotation accumulated over the relaxation cycles (rad): divided by the
        // physical time between samples it is the rotation rate in physical time (the
        // DEM spin at an equilibrium snapshot is only residual noise).
        std::vector<Vec3> rotation(sp.soil_count(), Vec3::Zero());
        // Creep readings are deformations at a held stress and in equilibrium (the reading
        // convention: engine/protocol/creep_hold.hpp).
        CreepHold holder(sp, sigma3, k_skel, v_max, shear_speed, scheme.loading.consolidation_tolerance, hold_options);

        // ---- multi-stage creep in physical time --------------------------------
        creep::RateProcessParams cp;
        const double vs = scheme.effects.contact_creep_viscosity ? scheme.effects.viscosity_scale : 0.0;
        cp.slip_rate_a_m_s = scheme.creep.slip_rate_a_m_s * vs;
        cp.slip_beta = scheme.creep.slip_beta;
        cp.slip_capacity_m = scheme.creep.slip_hardening_length_m;
        cp.capacity_offset = scheme.creep.capacity_offset;
        cp.aging_margin = scheme.creep.aging_margin;
        cp.critical_mobilisation = scheme.creep.critical_mobilisation;
        cp.flow_rate_scale = scheme.creep.flow_rate_scale;
        cp.wear_length_m = scheme.creep.wear_length_m;
        cp.wear_max = scheme.creep.wear_max;
        cp.flow_wear_length_m = scheme.creep.flow_wear_length_m;
        cp.slow_slip_wear_max = scheme.creep.slow_slip_wear_max;
        cp.slow_slip_wear_length_m = scheme.creep.slow_slip_wear_length_m;
        cp.corroded_bond_friction_loss = scheme.creep.corroded_bond_friction_loss;
        cp.bond_corrosion_b1_per_s = scheme.creep.damage_rate_b1_per_s * vs *
                                     (scheme.effects.grain_breakage ? scheme.effects.breakage_damage_scale : 1.0);
        cp.bond_corrosion_b2 = scheme.creep.damage_b2;
        cp.bond_corrosion_threshold = scheme.creep.damage_threshold;
        cp.soil_group = kSoilGroup;
        creep::RateProcessCreep creep_law(cp);
        GrainFatigueParams fatigue;  // static fatigue of crushable grains (creep stages only)
        fatigue.time_s = vs > 0.0 ? scheme.creep.grain_fatigue_time_s / vs : 0.0;  // creep effect off: none
        fatigue.exponent = scheme.creep.grain_fatigue_exponent;
        fatigue.ratio_cap = scheme.creep.grain_fatigue_ratio_cap;
        switch (scheme.creep.grain_fatigue_drive) {
            case GrainFatigueDrive::CappedPeakForce: fatigue.drive = FatigueDrive::CappedPeakForce; break;
            case GrainFatigueDrive::PeakForce: fatigue.drive = FatigueDrive::PeakForce; break;
            case GrainFatigueDrive::GrainStress: fatigue.drive = FatigueDrive::GrainStress; break;
        }
        fatigue.instant_life_s = scheme.creep.grain_fatigue_instant_life_s;
        fatigue.strength_spread = scheme.creep.grain_fatigue_strength_spread;

        const double hc = sp.height();  // reference height of the creep test
        const double z_top0 = sp.top_z();
        const double H = scheme.specimen.height_m;
        // Measurement spheres on the axis at z = +0.4 H, 0, -0.4 H (+-80 mm for 200 mm),
        // radius max(0.15 D, 1.5 mean grain diameters) (15 mm for the paper's specimen): the
        // paper's 5 mm holds no grain of a coarse soil; this holds some grains yet stays
        // clear of platens and membrane.
        res.measurement_sphere_radius_m = std::max(0.15 * scheme.specimen.diameter_m, 1.5 * sp.mean_diameter());
        std::vector<MeasurementSphere> spheres;
        for (double z : {0.4 * H, 0.0, -0.4 * H}) spheres.emplace_back(Vec3(0, 0, z), res.measurement_sphere_radius_m);
        for (auto& m : spheres) m.set_reference(w);
        double last_sample_t = 0.0;
        auto sample_spheres = [&](double t) {
            const double span = t - last_sample_t;
            for (int s = 0; s < 3; ++s) {
                const auto r = spheres[s].measure(w);
                Vec3 rot = Vec3::Zero();
                int inside = 0;
                for (int i = 0; i < sp.soil_count(); ++i)
                    if ((w.particles().position[i] - spheres[s].center()).norm() <= spheres[s].radius()) {
                        rot += rotation[i];
                        ++inside;
                    }
                const Vec3 rate = (inside > 0 && span > 0.0) ? Vec3(rot / (inside * span)) : Vec3(Vec3::Zero());
                MeasurementSample ms;
                ms.sphere = s + 1;
                ms.step = w.step();
                ms.time_s = t;
                ms.z_displacement_m = r.mean_displacement.z();
                ms.rotation_rate_x_rad_s = rate.x();
                ms.rotation_rate_y_rad_s = rate.y();
                ms.rotation_rate_z_rad_s = rate.z();
                ms.porosity = r.porosity;
                ms.coordination = r.coordination;
                res.measurements.push_back(ms);
                obs.measurement_sample(ms);
            }
            for (auto& r : rotation) r.setZero();
            last_sample_t = t;
        };
        // Instantaneous crushing (fatigue.instant_life_s > 0): grains whose life at the present
        // forces is shorter than that fail together, one relaxation passes their load on, and
        // again while any remain. No physical time passes: it is part of the response to the
        // load, not a step for the schedule to resolve (without it such grains stall the
        // piece loop in ever shorter pieces). Returns the grains failed.
        auto instant_crushing = [&](double q_target) {
            long total = 0;
            for (int round = 0; round < 200; ++round) {
                const long m = sp.fail_short_lived_grains(fatigue);
                if (m == 0) break;
                total += m;
                holder.hold(sigma3 + q_target, 100, 20000, &rotation, false);
                ++res.creep_relaxations;
            }
            return total;
        };
        double t_total = 0.0;
        for (int k = 0; k < n_stages; ++k) {
            const double S = scheme.loading.stress_levels[k];
            const double q_target = scheme.loading.stress_level_definition == StressLevelDefinition::PaperEq1
                                        ? deviator_for_stress_level_eq1(S, sigma3, scheme.loading.cohesion_pa,
                                                                        scheme.loading.friction_angle_deg)
                                        : S * q_peak;
            const std::string stage = "creep-" + std::to_string(k + 1);
            obs.stage_changed(stage, k + 1, S, q_target);
            CreepStageResult st;
            st.stage = k + 1;
            st.q_pa = q_target;
            st.stress_level = q_peak > 0.0 ? q_target / q_peak : 0.0;
            st.stress_level_eq1 = stress_level_eq1(q_target, sigma3, scheme.loading.cohesion_pa, scheme.loading.friction_angle_deg);
            st.duration_s = scheme.loading.stage_durations_s[k];
            st.start_time_s = t_total;
            const double d_before = z_top0 - sp.top_z();
            // The contacts have aged under the previous load (the consolidation, or the
            // previous stage); then the loading step: the instantaneous response.
            creep_law.age(w);
            holder.hold(sigma3 + q_target, 500, 200000, &rotation, true);
            st.instant_failed_grains = static_cast<int>(instant_crushing(q_target));
            creep_law.forget_sliding(w);
            auto record = [&](double t_stage) {
                const double d = z_top0 - sp.top_z();
                CreepPoint cpnt{t_total + t_stage, d, d / hc};
                st.raw.push_back(cpnt);
                obs.creep_point(k + 1, cpnt);
                const auto es = energy_sample(w, 2 + k, t_total + t_stage);
                res.energies.push_back(es);
                obs.energy_sample(es);
            };
            record(0.0);
            sample_spheres(t_total);
            const double d_loading = z_top0 - sp.top_z() - d_before;
            const auto dts = creep::creep_time_increments(st.duration_s, scheme.creep.first_increment_s,
                                                          scheme.creep.increment_growth, scheme.creep.max_increment_s);
            double t = 0.0;
            for (std::size_t n = 0; n < dts.size(); ++n) {
                const double d_increment_start = z_top0 - sp.top_z();
                // Split the increment while it would relax too much shear force at once:
                // the mechanical relaxation then follows the creep (increment convergence).
                double left = dts[n];
                while (left > 0.0) {
                    instant_crushing(q_target);
                    double h = left;
                    // A grain fatigued to failure (D_max) within the piece ends it: the
                    // broken grain's load must move to its neighbours (relaxation) before
                    // their fatigue goes on, so a fibre-bundle cascade is resolved one
                    // redistribution at a time and the failure times do not follow the
                    // schedule. The piece overshoots the exact failure time by 1e-6 of it
                    // so that the exact update reaches D_max.
                    const double t_fail = sp.advance_fatigue(h, fatigue, false).next_failure_s;
                    if (t_fail < h) h = std::min(h, t_fail * (1.0 + 1e-6));
                    // ... or would fatigue a grain by more than a tenth of its strength.
                    for (int halving = 0; halving < 8 && (creep_law.trial(w, h).relaxation >
                                                              scheme.creep.max_relaxation_per_increment ||
                                                          sp.advance_fatigue(h, fatigue, false).max_increment > 0.1);
                         ++halving)
                        h *= 0.5;
                    creep_law.advance(w, h);
                    const FatigueSummary fs = sp.advance_fatigue(h, fatigue);
                    const long crushed_before = sp.crushing_events();
                    const long cycles = holder.hold(sigma3 + q_target, 100, 20000, &rotation, false);
                    ++res.creep_relaxations;
                    left = h < left ? left - h : 0.0;
                    CreepIncrementLog il;
                    il.stage = k + 1;
                    il.t_stage_s = t + (dts[n] - left);
                    il.dt_s = h;
                    il.hold_cycles = cycles;
                    il.crushing_events = sp.crushing_events() - crushed_before;
                    il.grains_at_strength = fs.grains_at_strength;
                    il.grains_failed = fs.grains_failed;
                    il.max_damage_increment = fs.max_increment;
                    il.max_force_ratio = fs.max_ratio;
                    il.deformation_m = z_top0 - sp.top_z();
                    obs.creep_increment(il);
                    // A collapse is read piece by piece: driven on, its relaxations run at
                    // their cycle cap, piece after piece, until the specimen finds a new
                    // equilibrium several per cent of strain later.
                    if (creep_collapse(il.deformation_m - d_increment_start, d_loading)) {
                        st.ruptured = true;
                        break;
                    }
                }
                t += dts[n] - left;
                record(t);
                if (n % 4 == 3 || n + 1 == dts.size()) sample_spheres(t_total + t);
                prog.report(stage, 2 + k, t / st.duration_s);
                // Creep rupture: the platen runs away beyond the shear test's range.
                if ((z_top0 - sp.top_z()) / hc > std::max(0.25, eps_max + 0.05)) st.ruptured = true;
                // (... or it collapsed within the increment, above.)
                if (st.ruptured) {
                    st.rupture_time_s = t;
                    break;
                }
            }
            // Per-stage curves and summary numbers.
            std::vector<creep::TimeDeformation> stage_raw;
            for (const auto& p : st.raw) stage_raw.push_back({p.time_s, p.axial_deformation_m});
            std::vector<creep::TimeDeformation> tr =
                creep::translate_stage(stage_raw, st.start_time_s, st.start_time_s + t, d_before);
            for (const auto& p : tr) st.translated.push_back({p.time, p.deformation, p.deformation / hc});
            st.instant_deformation_m = st.translated.front().axial_deformation_m;
            st.final_deformation_m = st.translated.back().axial_deformation_m;
            const double creep_part = st.final_deformation_m - st.instant_deformation_m;
            st.elastic_share = st.final_deformation_m > 0.0 ? st.instant_deformation_m / st.final_deformation_m : 1.0;
            const double d30 = deformation_at(st, 1800.0);
            st.share_in_first_30min = creep_part > 0.0 ? std::clamp((d30 - st.instant_deformation_m) / creep_part, 0.0, 1.0) : 1.0;
            st.total_share_in_first_30min =
                st.final_deformation_m > 0.0 ? std::clamp(d30 / st.final_deformation_m, 0.0, 1.0) : 1.0;
            const CreepRegime regime = classify_creep_regime(st, t);
            st.accelerating = regime.accelerating;
            st.converged = regime.converged;
            for (double d : sp.fatigue_damage()) st.failed_grains += d >= kFatigueDamageMax ? 1 : 0;
            res.creep_stages.push_back(st);
            t_total += t;
            if (st.ruptured) break;
        }
        res.total_steps = shear_steps + w.step();
    } catch (const Progress::Cancelled&) {
        res.cancelled = true;
        res.converged = false;
    }
    res.wall_time_s = prog.elapsed();
    obs.stage_changed("done", 0, 0.0, 0.0);
    return res;
}

}  // namespace triax::protocol
