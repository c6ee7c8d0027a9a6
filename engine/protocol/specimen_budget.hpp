#pragma once
// SpecimenBudget: how large a scheme's specimen will be, estimated before anything is
// generated (no radius is drawn), so that a caller can refuse or queue it.
//
// Grains: the expected count of SpecimenBuilder's draw (gradation.hpp draw_radii) for the
// solid volume V_s = (1 - n) pi (D/2)^2 H. Radii uniform by number in [a, b] have the mean
// volume (4/3) pi (b^4 - a^4) / (4 (b - a)) (a^3 when a = b); a sieve curve's classes each
// take their mass share of V_s. With max_particles > 0 and more grains than that, the
// builder scales every size by f = cbrt(N / max_particles) x 1.02, so the count becomes
// N / f^3. The membrane count is the Membrane lattice (engine/boundary/membrane.cpp) for the
// radius the builder picks. Contacts: about 3 per grain (coordination ~6) and 3 per
// membrane particle (its six lattice bonds).
//
// Limits (kMax* below) are hard: TestScheme::validate refuses a scheme over any of them,
// whatever max_particles says, because the builder draws the uncapped radii first.
#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

struct SpecimenBudget {
    long long grains;              // soil grains the specimen will hold (after the max_particles cap)
    long long membrane_particles;  // membrane lattice spheres
    long long contacts_estimate;   // contacts and bonds in the store at equilibrium
    double memory_bytes;           // peak memory of building and running the specimen (bytes)
};

// Uncapped grain count the builder draws before applying max_particles (its transient
// peak; drawing and sorting them is not polled for cancel and takes about half a second).
inline constexpr long long kMaxDrawnGrains = 5'000'000;
// Simulated particles, grains + membrane.
inline constexpr long long kMaxSpecimenParticles = 2'000'000;
// Peak memory of one specimen.
inline constexpr double kMaxSpecimenMemoryBytes = 4.0 * 1024.0 * 1024.0 * 1024.0;

// Throws InputError naming the gradation field when the gradation itself is invalid.
SpecimenBudget estimate_specimen_size(const TestScheme& s);

// Expected grain count of the uncapped draw (before max_particles), as a double so that a
// hostile gradation (r_min 1e-9 m) reports its real size instead of overflowing.
double estimate_drawn_grains(const TestScheme& s);

// Throws InputError naming the field to change when the specimen is over a limit above.
void check_specimen_budget(const TestScheme& s);

}  // namespace triax::protocol
