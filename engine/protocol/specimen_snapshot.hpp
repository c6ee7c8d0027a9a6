#pragma once
// SpecimenSnapshot: the state of the specimen at the end of a stage, as plain data for
// whoever stores, draws or exports it (server/io/packing_*.cpp). Recorded at the end of
// generation ("generation"), consolidation ("consolidation"), shear ("shear") and each
// creep stage ("creep-1", ...) and delivered through RunObserver::on_snapshot.
//
// SI units (m, N, rad, kg/m^3); compression positive for normal forces. Particles are in
// the World's order (soil grains first, then the membrane), so contact indices i, j refer
// to positions in these arrays.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/types.hpp"

namespace triax {
class World;
}

namespace triax::protocol {

class Specimen;
struct TestScheme;

// A rigid boundary: a plane wall through `point` with unit `normal` pointing into the
// specimen, and the force the particles exert on it (N, along -normal, compression positive).
struct SnapshotPlaten {
    std::string name;     // "bottom", "top" (cylindrical specimen); "x-", "x+", ... (box)
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
    double normal_force_n = 0.0;
};

struct SnapshotSphere {
    Vec3 center = Vec3::Zero();  // m
    double radius_m = 0.0;
};

struct SpecimenSnapshot {
    std::string stage;
    long step = 0;  // the World's mechanical step at which it was taken

    // Per particle.
    std::vector<Vec3> position;           // m
    std::vector<double> radius;           // m
    std::vector<double> density;          // kg/m^3 (true, not density-scaled)
    // The World's own mass and moment of inertia (true, not density-scaled), kept bit for
    // bit: a generated grain's mass is its drawn mass times the growth factors, which is not
    // density x 4/3 pi r^3 to the last bit, and an exact restart needs the very bits.
    std::vector<double> mass;             // kg
    std::vector<double> inertia;          // kg m^2
    // The grain radii the specimen's stiffness, time step and membrane were sized from (m;
    // 0 = not a triaxial specimen): see ImportedPacking.
    double sizing_mean_radius_m = 0.0;
    double sizing_min_radius_m = 0.0;
    std::vector<int> group;               // 0 grain, 1 membrane (specimen.hpp), box groups as the caller's
    std::vector<Vec3> velocity;           // m/s (residual at equilibrium; kept for an exact restart)
    std::vector<Vec3> angular_velocity;   // rad/s
    std::vector<Vec3> displacement;       // m, since the start of consolidation (zero before it)
    std::vector<Vec3> rotation;           // rad, accumulated rotation vector since the start of consolidation
    std::vector<std::uint8_t> crushed;    // 1: the grain crushed (a plastic contact or fatigue failure)

    // Per active or bonded particle-particle contact.
    std::vector<int> contact_i, contact_j;       // indices into the particle arrays, i < j
    std::vector<std::uint8_t> bonded;            // contact bond intact
    std::vector<double> normal_force_n;          // N, compression positive
    std::vector<Vec3> shear_force_n;             // N, on j
    std::vector<double> bond_normal_strength_n;  // N (0 when unbonded)
    std::vector<double> bond_shear_strength_n;   // N

    std::vector<SnapshotPlaten> platens;
    std::vector<SnapshotSphere> measurement_spheres;
    // Group names, indexed by group tag ("grain", "membrane", "platen").
    std::vector<std::string> group_names;

    std::size_t particle_count() const { return position.size(); }
    std::size_t contact_count() const { return contact_i.size(); }
    // Particles of a group.
    std::size_t count_of(int g) const;
};

// The three measurement spheres of the protocol: on the axis at z = +0.4 H, 0, -0.4 H,
// radius max(0.15 D, 1.5 mean grain diameters) (triaxial_test.cpp reads them).
std::vector<SnapshotSphere> measurement_sphere_layout(const TestScheme& scheme, double mean_diameter_m);

// Every particle, contact and platen of a World: the generic part, for any specimen
// (the box of bench/cross_engine uses it directly). `reference` and `rotation` may be
// empty (zero displacement and rotation); `crushed` likewise.
SpecimenSnapshot snapshot_of_world(const World& world, const std::string& stage, const std::vector<Vec3>& reference,
                                   const std::vector<Vec3>& rotation, const std::vector<std::uint8_t>& crushed);

// The triaxial specimen: grains, membrane, the two platens, the measurement spheres.
SpecimenSnapshot snapshot_of(const Specimen& specimen, const TestScheme& scheme, const std::string& stage);

}  // namespace triax::protocol
