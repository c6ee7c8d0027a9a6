#include "engine/protocol/run_estimate.hpp"

#include "engine/boundary/membrane.hpp"
#include "engine/core/types.hpp"
#include "engine/creep/time_schedule.hpp"
#include "engine/protocol/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace triax::protocol {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kInertialTarget = 5.0e-4;  // triaxial_test.cpp: quasi-static shear rate

std::string short_number(double v) {
    std::ostringstream o;
    o.precision(3);
    o << v;
    return o.str();
}

// Mean and extreme grain radii of the specimen Specimen builds (after the max_particles
// scaling, as specimen_budget.cpp counts them).
struct Radii {
    double min = 0.0, mean = 0.0, max = 0.0;
};

Radii grain_radii(const TestScheme& s) {
    const double vs = (1.0 - s.specimen.target_porosity) * kPi * 0.25 * s.specimen.diameter_m * s.specimen.diameter_m *
                      s.specimen.height_m;
    double n = 0.0, rsum = 0.0;
    Radii r{1e9, 0.0, 0.0};
    for (const auto& k : size_classes(s.gradation)) {
        const double a = k.r_lo_m, b = std::max(k.r_hi_m, k.r_lo_m);
        const double v = b > a ? 4.0 / 3.0 * kPi * (b * b * b * b - a * a * a * a) / (4.0 * (b - a)) : 4.0 / 3.0 * kPi * a * a * a;
        const double c = k.mass_fraction * vs / v;
        n += c;
        rsum += c * 0.5 * (a + b);
        r.min = std::min(r.min, a);
        r.max = std::max(r.max, b);
    }
    r.mean = n > 0.0 ? rsum / n : 0.0;
    if (s.max_particles > 0 && n > s.max_particles) {
        const double f = std::cbrt(n / s.max_particles) * 1.02;
        r.min *= f;
        r.mean *= f;
        r.max *= f;
    }
    return r;
}
}  // namespace

void check_membrane_holds_grains(const TestScheme& s) {
    if (s.specimen.lateral_boundary == SpecimenSpec::LateralBoundary::GrainPressure) return;
    const double rm = s.micro.membrane_particle_radius_m;
    if (!(rm > 0.0)) return;  // automatic: never smaller than the smallest grain
    const Radii r = grain_radii(s);
    if (r.min <= boundary::kMaxGrainToMembraneRadius * rm) return;
    const double need = r.min / boundary::kMaxGrainToMembraneRadius;
    throw InputError("micro.membrane_particle_radius_m: membrane spheres of " + short_number(rm * 1e3) +
                     " mm cannot hold grains of " + short_number(r.min * 1e3) + " mm and more" +
                     (s.max_particles > 0 ? " (the smallest grain once max_particles scales the gradation up)" : "") +
                     ": grains escape under the membrane in consolidation; set it to at least " + short_number(need * 1e3) +
                     " mm, or 0 for the automatic size" + (s.max_particles > 0 ? ", or raise max_particles" : ""));
}

RunEstimate estimate_run(const TestScheme& s) {
    s.validate();
    RunEstimate e;
    e.size = estimate_specimen_size(s);
    const Radii r = grain_radii(s);
    e.grain_mean_radius_m = r.mean;
    e.grain_max_radius_m = r.max;
    double rm = s.micro.membrane_particle_radius_m;
    if (rm <= 0.0) rm = boundary::automatic_membrane_radius(r.min, r.mean, s.specimen.diameter_m);
    e.membrane_radius_m = s.specimen.lateral_boundary == SpecimenSpec::LateralBoundary::GrainPressure ? 0.0 : rm;

    // Time step as Specimen sets it (specimen.cpp).
    const double rho_s = s.specimen.dry_density_kg_m3 / (1.0 - s.specimen.target_porosity);
    const double kn = 0.5 * kPi * r.mean * s.micro.normal_modulus_pa;
    const double r_dt = std::max(r.min, 0.2 * r.mean);
    const double m_dt = rho_s * 4.0 / 3.0 * kPi * r_dt * r_dt * r_dt;
    e.time_step_s = 0.5 * std::sqrt(m_dt / kn);

    const double g = static_cast<double>(std::max<long long>(1, e.size.grains));
    const double w = std::clamp(std::log(g / 300.0) / std::log(1000.0 / 300.0), 0.0, 1.0);
    const auto consolidation_typical = static_cast<long long>(
        std::exp((1.0 - w) * std::log(double(kConsolidationSmallSpecimenSteps)) + w * std::log(double(kConsolidationLargeSpecimenSteps))));
    e.consolidation = {kConsolidationMinSteps, consolidation_typical, kConsolidationMaxSteps};
    const double p0 = std::max(s.loading.confining_pressure_pa, 1.0);
    const double rate = kInertialTarget * std::sqrt(p0 / rho_s) / (2.0 * r.mean);
    const auto shear = static_cast<long long>(std::ceil(s.loading.max_axial_strain / (rate * e.time_step_s)));
    e.shear = {shear / 2, shear, shear};

    const std::size_t stages = s.loading.stress_levels.size();
    long long increments = 0;
    for (std::size_t k = 0; k < stages && k < s.loading.stage_durations_s.size(); ++k)
        increments += static_cast<long long>(creep::creep_time_increments(s.loading.stage_durations_s[k], s.creep.first_increment_s,
                                                                          s.creep.increment_growth, s.creep.max_increment_s)
                                                 .size());
    e.creep_increments = static_cast<int>(increments);
    const auto n_stages = static_cast<long long>(stages);
    e.creep = {n_stages * kLoadingHoldMin + increments * kIncrementHoldMin,
               n_stages * kLoadingHoldTypical + increments * kIncrementHoldTypical,
               n_stages * kLoadingHoldMax + increments * kIncrementHoldMax};
    e.total = {e.consolidation.low + e.shear.low + e.creep.low, e.consolidation.typical + e.shear.typical + e.creep.typical,
               e.consolidation.high + e.shear.high + e.creep.high};

    // The threads share the particle loops; two threads do not halve the time.
    const double particles = static_cast<double>(e.size.grains + e.size.membrane_particles);
    const double speedup = s.threads > 1 ? std::min<double>(s.threads, 1.0 + (kTwoThreadSpeedup - 1.0) * (s.threads - 1)) : 1.0;
    const double per_step_low = particles * kSecondsPerParticleStepLow / speedup / 60.0;
    const double per_step_high = particles * kSecondsPerParticleStepHigh / speedup / 60.0;
    e.minutes_low = static_cast<double>(e.total.typical) * per_step_low;
    e.minutes_typical = static_cast<double>(e.total.typical) * 0.5 * (per_step_low + per_step_high);
    e.minutes_high = static_cast<double>(e.total.typical) * per_step_high;
    e.minutes_cap = static_cast<double>(e.total.high) * per_step_high;

    const double d_ratio = s.specimen.diameter_m / (2.0 * r.max);
    if (d_ratio < 6.0)
        e.warnings.push_back("the specimen is " + short_number(d_ratio) +
                             " largest grains across (a lab specimen is at least 6): its curves carry the noise of few grains; raise max_particles");
    if (e.size.membrane_particles > 2 * e.size.grains)
        e.warnings.push_back("the membrane has " + std::to_string(e.size.membrane_particles) + " particles for " +
                             std::to_string(e.size.grains) +
                             " grains and costs most of the time; a larger micro.membrane_particle_radius_mm makes it coarser");
    if (e.minutes_typical > 120.0)
        e.warnings.push_back("about " + short_number(e.minutes_typical / 60.0) +
                             " hours on this machine; lower max_particles or the stage durations for a first look");
    return e;
}

}  // namespace triax::protocol
