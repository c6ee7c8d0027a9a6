#pragma once
// Sphere state as a structure of arrays: one contiguous vector per field, so the
// force and integration loops stream through memory. Index = particle id; ids are
// stable for the life of a World (particles are never reordered behind the caller).
#include "engine/core/types.hpp"

#include <cstdint>
#include <vector>

namespace triax {

// Per-particle flags (bit set).
enum ParticleFlag : std::uint8_t {
    kFixedVelocity = 1,  // velocity and spin are prescribed: the integrator only moves it
    kClumpMember = 2,    // moved rigidly by its clump, never integrated on its own
};

struct ParticleArrays {
    std::vector<Vec3> position;          // m, centre
    std::vector<Vec3> velocity;          // m/s (held at half steps by the integrator)
    std::vector<Vec3> angular_velocity;  // rad/s
    std::vector<Vec3> force;             // N, net force of the last step (contacts + external + gravity)
    std::vector<Vec3> torque;            // N m, net torque of the last step
    std::vector<Vec3> external_force;    // N, applied by the caller (e.g. membrane pressure); its work is boundary work
    std::vector<double> radius;          // m
    std::vector<double> mass;            // kg (true gravitational mass)
    std::vector<double> inertia;         // kg m^2, 2/5 m r^2 for a solid sphere
    std::vector<int> group;              // group tag used to pick the contact law
    std::vector<int> clump_id;           // -1 when the sphere is free
    std::vector<std::uint8_t> flags;     // ParticleFlag bits

    std::size_t size() const { return position.size(); }

    // Appends a sphere and returns its index. Density in kg/m^3.
    int add(const Vec3& x, double r, double density, int group_tag) {
        position.push_back(x);
        velocity.push_back(Vec3::Zero());
        angular_velocity.push_back(Vec3::Zero());
        force.push_back(Vec3::Zero());
        torque.push_back(Vec3::Zero());
        external_force.push_back(Vec3::Zero());
        radius.push_back(r);
        const double m = density * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r;
        mass.push_back(m);
        inertia.push_back(0.4 * m * r * r);
        group.push_back(group_tag);
        clump_id.push_back(-1);
        flags.push_back(0);
        return static_cast<int>(position.size() - 1);
    }
};

}  // namespace triax
