#pragma once
// Rigid walls. Both kinds are velocity-controlled (the caller sets the velocity; the
// wall is moved kinematically) and accumulate the force the particles exert on them.
// Their work on the particles is booked as boundary work in the EnergyLedger.
#include "engine/core/types.hpp"

namespace triax {

// Infinite plane. Particles live on the side the unit normal points to; a particle
// whose centre is closer to the plane than its radius is in contact.
struct PlaneWall {
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();     // unit, points into the particle side
    Vec3 velocity = Vec3::Zero();    // m/s, translation imposed by the caller
    int group = 0;                   // group tag for the contact law table
    Vec3 force = Vec3::Zero();       // N, force exerted BY the particles ON the wall, last step
    int contact_count = 0;           // particles touching, last step

    // Normal stress on the wall, compression positive, for an area in m^2 (Pa).
    double normal_stress(double area) const { return -force.dot(normal) / area; }
};

// Finite circular cylinder holding the particles inside. Axis through `base` along
// the unit `axis`; the wall spans axial coordinates [0, height] from the base.
// The radius can change at `radial_velocity` (m/s, positive = expanding).
struct CylinderWall {
    Vec3 base = Vec3::Zero();
    Vec3 axis = Vec3::UnitZ();
    double radius = 1.0;             // m
    double height = 1.0;             // m
    Vec3 velocity = Vec3::Zero();    // m/s, translation of the whole cylinder
    double radial_velocity = 0.0;    // m/s
    int group = 0;
    Vec3 force = Vec3::Zero();       // N, force by particles on the wall, last step
    double radial_force = 0.0;       // N, sum of outward normal force magnitudes, last step
    int contact_count = 0;

    // Mean radial (confining) stress on the lateral surface, compression positive (Pa).
    double radial_stress() const {
        return radial_force / (2.0 * 3.14159265358979323846 * radius * height);
    }
};

}  // namespace triax
