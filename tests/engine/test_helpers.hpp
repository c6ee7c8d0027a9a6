#pragma once
// Small builders shared by the engine tests.
#include "engine/core/world.hpp"

#include <cmath>
#include <cstring>
#include <vector>

namespace triax::test {

constexpr double kPi = 3.14159265358979323846;

inline ContactLaw linear_law(double kn, double ks, double mu) {
    ContactLaw law;
    law.kn = kn;
    law.ks = ks;
    law.friction = mu;
    return law;
}

inline double sphere_mass(double r, double rho) { return rho * 4.0 / 3.0 * kPi * r * r * r; }

// Bit for bit the same contents (a faster path must give the scalar path's bits).
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace triax::test

#include <cstdint>
#include <vector>

namespace triax::test {

// Deterministic uniform numbers in [0, 1) (portable, unlike std distributions).
struct Rng {
    std::uint64_t s;
    explicit Rng(std::uint64_t seed) : s(seed * 2654435761ULL + 1) {}
    double uniform() {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
    }
};

struct SphereSpec { Vec3 x; double r; };

// Spheres on a jittered cubic lattice in the box [0, L]^3, radii uniform in
// [r_min, r_max]; lattice spacing 2 r_max (so nothing overlaps at start).
inline std::vector<SphereSpec> lattice_spheres(int per_side, double r_min, double r_max, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<SphereSpec> out;
    const double a = 2.05 * r_max;
    for (int z = 0; z < per_side; ++z)
        for (int y = 0; y < per_side; ++y)
            for (int x = 0; x < per_side; ++x) {
                const double r = r_min + (r_max - r_min) * rng.uniform();
                const double slack = a / 2 - r;
                out.push_back({Vec3((x + 0.5) * a + slack * (rng.uniform() - 0.5),
                                    (y + 0.5) * a + slack * (rng.uniform() - 0.5),
                                    (z + 0.5) * a + slack * (rng.uniform() - 0.5)), r});
            }
    return out;
}

// A box of six plane walls around [0, L]^3 (normals inward); returns the top wall index.
inline int add_box(World& w, double L) {
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitX());
    w.add_plane_wall(Vec3(L, 0, 0), -Vec3::UnitX());
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitY());
    w.add_plane_wall(Vec3(0, L, 0), -Vec3::UnitY());
    w.add_plane_wall(Vec3(0, 0, 0), Vec3::UnitZ());
    return w.add_plane_wall(Vec3(0, 0, L), -Vec3::UnitZ());
}

}  // namespace triax::test
