#pragma once
// ImportedPacking: grains made elsewhere (another DEM code, a CT scan, an earlier run's
// export) that become the specimen of a scheme: generation is skipped, the membrane and
// the platens are built around them from the scheme's geometry and the protocol runs from
// there (Specimen's constructor). Plain data; the parsers live in server/io/packing_*.cpp.
//
// SI units (m, m/s, rad/s). Only grains are listed: membrane particles and platens of a
// file are rebuilt from the scheme, not imported.
#include <string>
#include <vector>

#include "engine/core/types.hpp"

namespace triax::protocol {

struct TestScheme;

struct ImportedPacking {
    std::string source;                  // file name or "upload", for messages
    std::vector<Vec3> position;          // m, specimen axis z, centre at the origin
    std::vector<double> radius;          // m
    std::vector<int> line;               // where each grain was read (1-based line; 0 = unknown)
    // Residual velocities of an exported equilibrium state (empty = at rest): with them an
    // export re-imported continues exactly as the run it came from.
    std::vector<Vec3> velocity;          // m/s
    std::vector<Vec3> angular_velocity;  // rad/s
    // The platens' last reading (N, compression positive; bottom, top) of an exported state:
    // the consolidation servo's first command reads it (empty = none, the platens start unloaded).
    std::vector<double> platen_force_n;
    // The grains' mass and moment of inertia of an exported state (empty = from the scheme's
    // grain density and the radius): an exact restart needs the exporting World's own bits.
    std::vector<double> mass;     // kg
    std::vector<double> inertia;  // kg m^2
    // The grain radii an exported specimen's contact stiffness, time step and membrane were
    // sized from (m; 0 = from `radius`): generated grains grow to their drawn radii only
    // to the last bits, and the exact restart needs the very sizing.
    double mean_radius_m = 0.0;
    double min_radius_m = 0.0;

    std::size_t size() const { return position.size(); }
};

// Tolerances of validate_packing, as fractions of the smaller radius of a pair.
struct PackingTolerance {
    // A grain pair may overlap by at most this x r_min of the pair. Radius expansion locks
    // overlaps of a few per cent into generated packings, and up to 27.5 % into the
    // 60-grain specimen of tests/protocol/packing_round_trip_test.cpp on one build (the
    // locked overlap depends on the trajectory's last bits); the engine's own packings must
    // import on any build. A radius written as a diameter, or a wrong unit, gives 100 % and more.
    double overlap = 0.5;
    double outside = 0.05;   // a grain may cross a platen by this x its radius (its centre must be inside the cylinder)
};

// Checks the packing against the scheme's specimen (a cylinder of diameter D and height H,
// axis z, centred at the origin): at least one grain, finite positive radii, no grain
// outside the cylinder or the platens, no pair overlapping beyond the tolerance. Throws
// InputError naming the line of the first offending grain (and of its partner).
void validate_packing(const ImportedPacking& p, const TestScheme& scheme, const PackingTolerance& tol = {});

}  // namespace triax::protocol
