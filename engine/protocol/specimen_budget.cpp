#include "engine/protocol/specimen_budget.hpp"

#include "engine/boundary/membrane.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "engine/core/types.hpp"
#include "engine/protocol/gradation.hpp"

namespace triax::protocol {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Bytes per particle: ParticleArrays (6 Vec3 + 3 double + 2 int + flags = 177 B), the cell
// list entry, the builder's placement point and crushing force, rounded up.
constexpr double kBytesPerParticle = 256.0;
// Bytes per contact: ContactStore's columns (6 Vec3, 11 double, 3 int, 3 flags = 251 B),
// its pair key and the neighbour candidate pairs (Verlet skin), rounded up.
constexpr double kBytesPerContact = 384.0;
constexpr double kContactsPerGrain = 3.0;
constexpr double kContactsPerMembraneParticle = 3.0;

// Mean volume and mean radius of radii uniform in [a, b].
double mean_sphere_volume(double a, double b) {
    if (!(b > a)) return 4.0 / 3.0 * kPi * a * a * a;
    return 4.0 / 3.0 * kPi * (b * b * b * b - a * a * a * a) / (4.0 * (b - a));
}

struct GrainEstimate {
    double count = 0.0;        // expected number of grains drawn
    double mean_radius_m = 0.0;
    double min_radius_m = 0.0;
};

GrainEstimate estimate_grains(const GradationSpec& g, double solid_volume_m3) {
    GrainEstimate e;
    double rsum = 0.0;
    e.min_radius_m = gradation_r_min_m(g);
    for (const auto& k : size_classes(g)) {
        const double n = k.mass_fraction * solid_volume_m3 / mean_sphere_volume(k.r_lo_m, k.r_hi_m);
        e.count += n;
        rsum += n * 0.5 * (k.r_lo_m + k.r_hi_m);
    }
    e.mean_radius_m = e.count > 0.0 ? rsum / e.count : 0.0;
    return e;
}

double solid_volume_m3(const TestScheme& s) {
    const double r = 0.5 * s.specimen.diameter_m;
    return (1.0 - s.specimen.target_porosity) * kPi * r * r * s.specimen.height_m;
}

// Membrane lattice of engine/boundary/membrane.cpp for the radius specimen.cpp picks.
double membrane_count(const TestScheme& s, double grain_min_radius_m, double grain_mean_radius_m) {
    if (s.specimen.lateral_boundary == SpecimenSpec::LateralBoundary::GrainPressure) return 0.0;
    double rm = s.micro.membrane_particle_radius_m;
    if (rm <= 0.0) rm = boundary::automatic_membrane_radius(grain_min_radius_m, grain_mean_radius_m, s.specimen.diameter_m);
    if (!(rm > 0.0)) return 0.0;
    const double rc = 0.5 * s.specimen.diameter_m + rm;
    const double n_theta = std::max(8.0, std::round(kPi / std::asin(std::min(1.0, rm / rc))));
    const double n_z = std::max(3.0, std::floor(s.specimen.height_m / (2.0 * rm)));
    return n_theta * n_z;
}

std::string about(double v) {
    std::ostringstream o;
    o.precision(3);
    o << v;
    return o.str();
}

// The field whose value sets the grains' size: the smallest radius of the gradation.
std::string grain_size_field(const TestScheme& s) {
    return s.gradation.kind == GradationSpec::Kind::RadiusRatio ? "gradation.r_min_m" : "gradation.sieve_curve[0]";
}

struct Sizes {
    double drawn = 0.0, grains = 0.0, membrane = 0.0, contacts = 0.0, memory = 0.0;
};

Sizes sizes(const TestScheme& s) {
    Sizes z;
    const double vs = solid_volume_m3(s);
    const GrainEstimate drawn = estimate_grains(s.gradation, vs);
    z.drawn = drawn.count;
    GrainEstimate kept = drawn;
    if (s.max_particles > 0 && drawn.count > s.max_particles) {
        const double f = std::cbrt(drawn.count / s.max_particles) * 1.02;
        kept.count = drawn.count / (f * f * f);
        kept.mean_radius_m *= f;
        kept.min_radius_m *= f;
    }
    z.grains = std::ceil(kept.count);
    z.membrane = membrane_count(s, kept.min_radius_m, kept.mean_radius_m);
    z.contacts = kContactsPerGrain * z.grains + kContactsPerMembraneParticle * z.membrane;
    // Peak: the uncapped draw (a vector of radii, doubled while it grows) is freed before
    // the particles exist; the run holds the specimen and one copy of it (the creep
    // stages start from a copy of the sheared specimen, triaxial_test.cpp).
    const double draw_bytes = 2.0 * 8.0 * z.drawn;
    const double run_bytes = 2.0 * (kBytesPerParticle * (z.grains + z.membrane) + kBytesPerContact * z.contacts);
    z.memory = std::max(draw_bytes, run_bytes);
    return z;
}

long long to_count(double v) {
    return v >= 9.0e18 ? 9'000'000'000'000'000'000LL : static_cast<long long>(v);
}
}  // namespace

double estimate_drawn_grains(const TestScheme& s) {
    return estimate_grains(s.gradation, solid_volume_m3(s)).count;
}

SpecimenBudget estimate_specimen_size(const TestScheme& s) {
    const Sizes z = sizes(s);
    return {to_count(z.grains), to_count(z.membrane), to_count(z.contacts), z.memory};
}

void check_specimen_budget(const TestScheme& s) {
    const Sizes z = sizes(s);
    const std::string grains_field = grain_size_field(s);
    if (!(z.drawn <= kMaxDrawnGrains))
        throw InputError(grains_field + ": the gradation gives about " + about(z.drawn) +
                         " grains for this specimen (at most " + about(static_cast<double>(kMaxDrawnGrains)) +
                         " can be drawn, whatever max_particles says); use coarser grains or a smaller specimen");
    const bool membrane_dominates = z.membrane > z.grains;
    const std::string membrane_field = s.micro.membrane_particle_radius_m > 0.0 ? "micro.membrane_particle_radius_m"
                                                                                 : "specimen.diameter_m";
    const std::string field = membrane_dominates ? membrane_field : (s.max_particles > 0 ? "max_particles" : grains_field);
    if (!(z.grains + z.membrane <= kMaxSpecimenParticles))
        throw InputError(field + ": the specimen would hold about " + about(z.grains) + " grains and " +
                         about(z.membrane) + " membrane particles (at most " +
                         about(static_cast<double>(kMaxSpecimenParticles)) + " particles in all)");
    if (!(z.memory <= kMaxSpecimenMemoryBytes))
        throw InputError(field + ": the specimen would need about " + about(z.memory / 1.0e9) +
                         " GB of memory (at most " + about(kMaxSpecimenMemoryBytes / 1.0e9) + " GB)");
}

}  // namespace triax::protocol
