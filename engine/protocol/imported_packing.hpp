#pragma once
// ImportedPacking: grains made elsewhere (another DEM code, a CT scan, an earlier run's
// export) that become the specimen of a scheme: generation is skipped, the platens and
// the membrane are put back as the packing had them, or built around its grains as they
// are (packing_extent: a consolidated or sheared specimen keeps its own height and girth,
// and its grains their overlaps with the platens), and the protocol runs from there
// (Specimen's constructor). Plain data; the parsers live in server/io/packing_*.cpp.
//
// SI units (m, m/s, rad/s). Grains, the membrane's spheres of an exported state, and of
// the platens their heights and last force reading.
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
    // Where the platens were (m, bottom then top) in an exported state (empty = not named:
    // they are put against the outermost grains). A consolidated specimen's grains are
    // pressed into its platens by a fraction of a radius: the platens go back where they
    // were so that those contacts carry on as they were.
    std::vector<double> platen_z_m;
    // The grains' mass and moment of inertia of an exported state (empty = from the scheme's
    // grain density and the radius): an exact restart needs the exporting World's own bits.
    std::vector<double> mass;     // kg
    std::vector<double> inertia;  // kg m^2
    // The grain radii an exported specimen's contact stiffness, time step and membrane were
    // sized from (m; 0 = from `radius`): generated grains grow to their drawn radii only
    // to the last bits, and the exact restart needs the very sizing.
    // The membrane of an exported state (its spheres' centres, m, and radii, m, in the order
    // the export lists them: the lattice's, ring by ring from the bottom; empty = none). A
    // consolidated or sheared membrane is wrinkled and bulged, and its grains sit in its
    // gaps: it is restored as it was when it is the lattice the scheme builds (the same
    // count and sphere radius), else a fresh cylinder wraps the grains (packing_extent).
    std::vector<Vec3> membrane_position;
    std::vector<double> membrane_radius;
    double mean_radius_m = 0.0;
    double min_radius_m = 0.0;

    std::size_t size() const { return position.size(); }
};

// Tolerances of validate_packing.
struct PackingTolerance {
    // A grain pair may overlap by at most this x r_min of the pair. Radius expansion locks
    // overlaps of a few per cent into generated packings, and up to 27.5 % into the
    // 60-grain specimen of tests/protocol/packing_round_trip_test.cpp on one build (the
    // locked overlap depends on the trajectory's last bits); the engine's own packings must
    // import on any build. A radius written as a diameter, or a wrong unit, gives 100 % and more.
    double overlap = 0.5;
    // The grains' extent (their envelope: radius max(rho + r), heights min(z - r) ..
    // max(z + r)) may pass the scheme's specimen by at most this x its radius and
    // half-height, and must span at least (1 - extent) x its diameter and height. A test
    // deforms the specimen by some per cent (consolidation changes it by a few, a shear to
    // 15 % shortens it by 15 % and bulges it); a wrong unit is a factor 1000, a packing
    // with its origin at the base instead of the centre passes the top by H/2.
    double extent = 0.5;
};

// The specimen an imported packing makes: the fresh membrane's inner radius and the
// platens' heights (m, axis z). The platens are where the packing names them (platen_z_m),
// else against the outermost grains (min(z - r), max(z + r)). The radius is the grains'
// envelope max(rho + r), so that no grain starts inside a sphere of the fresh lattice.
// (A membrane the packing carries is restored instead, Specimen.)
struct PackingExtent {
    double radius_m = 0.0;
    double bottom_z_m = 0.0;
    double top_z_m = 0.0;
    double height_m() const { return top_z_m - bottom_z_m; }
    double centre_z_m() const { return 0.5 * (bottom_z_m + top_z_m); }
};
PackingExtent packing_extent(const ImportedPacking& p);

// Checks the packing against the scheme's specimen (a cylinder of diameter D and height H,
// axis z, centred at the origin): at least one grain, finite positive radii, the grains'
// extent matching the specimen within tol.extent, no pair overlapping beyond tol.overlap.
// Throws InputError naming the line of the first offending grain (and of its partner).
void validate_packing(const ImportedPacking& p, const TestScheme& scheme, const PackingTolerance& tol = {});

}  // namespace triax::protocol
