#include "engine/protocol/triaxial_test.hpp"

#include <memory>
#include <string>

#include "engine/protocol/consolidation.hpp"
#include "engine/protocol/creep_stage.hpp"
#include "engine/protocol/platen_servo.hpp"
#include "engine/protocol/run_context.hpp"
#include "engine/protocol/specimen.hpp"
#include "engine/protocol/specimen_snapshot.hpp"
#include "engine/protocol/stress_level.hpp"
#include "engine/protocol/triaxial_shear.hpp"

namespace triax::protocol {

namespace {

// Generation at the target porosity by radius expansion inside the held membrane.
std::unique_ptr<Specimen> generate_specimen(RunContext& run) {
    run.observer.stage_changed("generation", 0, 0.0, 0.0);
    run.progress.report("generation", 0, 0.0);
    RunObserver& obs = run.observer;
    auto sp = std::make_unique<Specimen>(run.scheme, [&obs] { return obs.cancel_requested(); });
    run.observer.stage_ended("generation", sp->world());
    run.observer.on_snapshot(snapshot_of(*sp, run.scheme, "generation"));
    run.result.particle_count = sp->soil_count();
    run.result.membrane_particle_count = sp->membrane_particle_count();
    run.result.initial_porosity = sp->porosity();
    return sp;
}

// The held deviator of creep stage k: q = S_k q_f, or from the paper's Eq. 1 (c, phi).
double stage_deviator(const TestScheme& s, int k, double q_failure_pa) {
    const double S = s.loading.stress_levels[k];
    if (s.loading.stress_level_definition == StressLevelDefinition::PaperEq1)
        return deviator_for_stress_level_eq1(S, s.loading.confining_pressure_pa, s.loading.cohesion_pa,
                                             s.loading.friction_angle_deg);
    return S * q_failure_pa;
}

// A run that ends before the creep stages: its steps are the one specimen's.
TestResult finish(TestResult& res, const Specimen& sp, RunObserver& obs, const Progress& progress) {
    res.total_steps = sp.world().step();
    res.wall_time_s = progress.elapsed();
    obs.stage_changed("done", 0, 0.0, 0.0);
    return std::move(res);
}

}  // namespace

TestResult run_triaxial_test(const TestScheme& scheme) {
    RunObserver none;
    return run_triaxial_test(scheme, none);
}

TestResult run_triaxial_test(const TestScheme& scheme, RunObserver& obs, Phase last) {
    scheme.validate();
    TestResult res;
    res.scheme_name = scheme.name;
    res.sigma3_pa = scheme.loading.confining_pressure_pa;
    const int n_stages = last == Phase::Creep ? static_cast<int>(scheme.loading.stress_levels.size()) : 0;
    Progress progress(obs, n_stages);
    RunContext run{scheme, res, obs, progress};
    try {
        // 1. The specimen, generated and isotropically consolidated to sigma3; the bonds
        //    (suction, cementation; moisture dependent) form and the grains become
        //    crushable on the consolidated fabric.
        std::unique_ptr<Specimen> specimen = generate_specimen(run);
        specimen->mark_reference();  // displacements and rotations are reported from here
        consolidate_isotropically(*specimen, run);
        specimen->install_soil_bonds();
        specimen->enable_crushing();
        obs.stage_ended("consolidation", specimen->world());
        obs.on_snapshot(snapshot_of(*specimen, scheme, "consolidation"));
        if (last == Phase::Consolidation) return finish(res, *specimen, obs, progress);
        // 2. The creep test runs on a second, identical consolidated specimen (the lab's
        //    q_f comes from a companion shear test; the graded creep loading starts from
        //    the isotropic state): a copy, as the engine is deterministic.
        std::unique_ptr<Specimen> creep_specimen = n_stages > 0 ? std::make_unique<Specimen>(*specimen) : nullptr;
        const PlatenServo servo = PlatenServo::for_specimen(*specimen);
        // 3. Strain-controlled shear to failure: q_f.
        const ShearOutcome shear = shear_to_failure(*specimen, run);
        obs.stage_ended("shear", specimen->world());
        obs.on_snapshot(snapshot_of(*specimen, scheme, "shear"));
        res.q_failure_pa = shear.q_failure_pa;
        res.axial_strain_at_failure = shear.axial_strain_at_failure;
        if (!creep_specimen) return finish(res, *specimen, obs, progress);
        // Steps of the shear specimen after the copy (the copy's history counts once).
        const long shear_steps = specimen->world().step() - creep_specimen->world().step();
        specimen.reset();
        // 4. Multi-stage creep at q_k = S_k q_f in physical time, until the last stage or a
        //    creep rupture.
        MultiStageCreep creep(*creep_specimen, servo, shear.q_failure_pa, run);
        for (int k = 0; k < n_stages; ++k) {
            const double q_k = stage_deviator(scheme, k, shear.q_failure_pa);
            obs.stage_changed("creep-" + std::to_string(k + 1), k + 1, scheme.loading.stress_levels[k], q_k);
            res.creep_stages.push_back(creep.run_stage(k, q_k));
            obs.stage_ended("creep-" + std::to_string(k + 1), creep_specimen->world());
            obs.on_snapshot(snapshot_of(*creep_specimen, scheme, "creep-" + std::to_string(k + 1)));
            if (res.creep_stages.back().ruptured) break;
        }
        res.total_steps = shear_steps + creep_specimen->world().step();
    } catch (const Progress::Cancelled&) {
        res.cancelled = true;
        res.converged = false;
    } catch (const SpecimenCancelled&) {  // polled inside generation and every chunk of cycles
        res.cancelled = true;
        res.converged = false;
    }
    res.wall_time_s = progress.elapsed();
    obs.stage_changed("done", 0, 0.0, 0.0);
    return res;
}

}  // namespace triax::protocol
