#include "engine/protocol/triaxial_shear.hpp"

#include <algorithm>
#include <cmath>

#include "engine/protocol/membrane_compliance.hpp"
#include "engine/protocol/platen_servo.hpp"

namespace triax::protocol {

namespace {
}  // namespace

ShearOutcome shear_to_failure(Specimen& sp, RunContext& run) {
    constexpr long kChunk = PlatenServo::kChunk;
    const TestScheme& scheme = run.scheme;
    TestResult& res = run.result;
    const double sigma3 = scheme.loading.confining_pressure_pa;
    run.observer.stage_changed("shear", 0, 0.0, 0.0);
    ShearOutcome out;
    double& q_peak = out.q_failure_pa;
    const double eps_max = scheme.loading.max_axial_strain;
    World& w = sp.world();
    const double dt = w.time_step();
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
    const double rate = run.scheme.loading.max_inertial_number * std::sqrt(p0 / rho_inertial) / sp.mean_diameter();
    const double seating = scheme.effects.seating_error ? scheme.effects.seating_displacement_m : 0.0;
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
                // Uncorrected hoop-tension of a real membrane adds to the measured q.
                q += membrane_hoop_deviator_pa(scheme.effects.membrane_modulus_pa, scheme.effects.membrane_thickness_m,
                                               scheme.specimen.diameter_m, eps_a);
            }
            pt.q_pa = q;
            pt.sigma1_pa = sigma3 + q;
            pt.sigma3_pa = sigma3;
            pt.p_pa = sigma3 + q / 3.0;
            pt.volumetric_strain = (v0 - sp.volume()) / v0;
            pt.inertial_number = rate * sp.mean_diameter() * std::sqrt(rho_inertial / std::max(pt.p_pa, 1.0));
            res.max_inertial_number = std::max(res.max_inertial_number, pt.inertial_number);
            res.shear.push_back(pt);
            run.observer.shear_point(pt);
            const auto es = energy_sample(w, 1, 0.0);
            res.energies.push_back(es);
            run.observer.energy_sample(es);
            if (q > q_peak) {
                q_peak = q;
                out.axial_strain_at_failure = pt.axial_strain;
            }
            run.progress.report("shear", 1, eps_a / eps_max);
        }
        if (eps_a >= eps_max) break;
        // Failure: a clear peak, then a 20 % drop (strain softening) ends the shear.
        if (run.scheme.loading.stop_at_softening && q_peak > 0.0 && !res.shear.empty() && res.shear.back().q_pa < 0.8 * q_peak && eps_a > 0.02) break;
    }
    w.plane_wall(sp.top_wall()).velocity.setZero();
    return out;
}

}  // namespace triax::protocol
