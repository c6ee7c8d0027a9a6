#pragma once
// The boundary's part of a step: the rigid walls are kinematic and move at the velocities
// the caller set (a plane translates; a cylinder translates and changes its radius). Their
// work on the particles is boundary work (J): -F_wall . V dt, for a cylinder also
// -radial_force * radial_velocity dt (F_wall: the force by the particles on the wall).
// Each wall's travel since the last neighbour rebuild (m) decides when the list must be
// rebuilt.
#include "engine/core/walls.hpp"
#include "engine/energy/energy_ledger.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

namespace triax {

// Moves the walls by one step of dt (s) and adds to `travel` (planes then cylinders).
// Books the work when `books` is given. Returns true when a wall has travelled more than
// half_skin (m) since the last rebuild.
inline bool move_walls(std::vector<PlaneWall>& planes, std::vector<CylinderWall>& cylinders,
                       std::vector<double>& travel, double dt, double half_skin, EnergyLedger* books) {
    std::size_t k = 0;
    for (PlaneWall& w : planes) {
        if (books) books->boundary_work += -w.force.dot(w.velocity) * dt;
        w.point += w.velocity * dt;
        travel[k++] += w.velocity.norm() * dt;
    }
    for (CylinderWall& w : cylinders) {
        if (books) books->boundary_work += (-w.force.dot(w.velocity) - w.radial_force * w.radial_velocity) * dt;
        w.base += w.velocity * dt;
        w.radius += w.radial_velocity * dt;
        travel[k++] += (w.velocity.norm() + std::abs(w.radial_velocity)) * dt;
    }
    bool far = false;
    for (double t : travel)
        if (t > half_skin) far = true;
    return far;
}

}  // namespace triax
