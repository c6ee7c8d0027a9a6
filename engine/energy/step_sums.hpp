#pragma once
// The energy ledger's side of a step: partial sums per block (contact slots, particles),
// reduced serially in block order and then booked into the EnergyLedger, so the books do
// not depend on the thread count. Energies in J, counts of bonds broken this step.
#include "engine/energy/energy_ledger.hpp"

#include <algorithm>
#include <vector>

namespace triax {

// Contacts' share of one block (or of the wall contacts, or of the whole step).
struct ContactSums {
    double strain = 0, bond_strain = 0, slip = 0, dashpot = 0, bond_break = 0;
    long broke_tension = 0, broke_shear = 0;
    // One contact's outcome (the evaluator's Outcome: energies and bond breaks of the step).
    template <class Outcome>
    void add(const Outcome& o) {
        strain += o.strain; bond_strain += o.bond_strain; slip += o.slip;
        dashpot += o.dashpot; bond_break += o.bond_break;
        broke_tension += o.broke_tension; broke_shear += o.broke_shear;
    }
    void add(const ContactSums& o) {
        strain += o.strain; bond_strain += o.bond_strain; slip += o.slip;
        dashpot += o.dashpot; bond_break += o.bond_break;
        broke_tension += o.broke_tension; broke_shear += o.broke_shear;
    }
};

// Why a particle failed the integrator's checks.
enum class Instability { none, non_finite_velocity, faster_than_radius, left_domain };

// Free spheres' share of one block of particles.
struct BodySums {
    double kinetic = 0, damping = 0, boundary = 0, body = 0;
    double max_disp2 = 0;                     // m^2, largest squared drift since the last rebuild
    long unstable = -1;                       // first particle that failed a check (-1: none)
    Instability cause = Instability::none;
    // The next block, in block order: energies add, the drift takes the maximum and the
    // first failure (lowest block) is kept.
    void add(const BodySums& s) {
        kinetic += s.kinetic; damping += s.damping; boundary += s.boundary; body += s.body;
        max_disp2 = std::max(max_disp2, s.max_disp2);
        if (unstable < 0 && s.unstable >= 0) { unstable = s.unstable; cause = s.cause; }
    }
};

// Sum of the blocks in block order, then `last` (the wall contacts' sums).
inline ContactSums reduce_in_block_order(const std::vector<ContactSums>& blocks, const ContactSums& last) {
    ContactSums total;
    for (const ContactSums& b : blocks) total.add(b);
    total.add(last);
    return total;
}
inline BodySums reduce_in_block_order(const std::vector<BodySums>& blocks) {
    BodySums total;
    for (const BodySums& s : blocks) total.add(s);
    return total;
}

// State terms (strain, bond strain) only when this step computed them; dissipations always.
inline void book_contacts(EnergyLedger& e, const ContactSums& total, bool state_energy) {
    if (state_energy) {
        e.strain = total.strain;
        e.bond_strain = total.bond_strain;
    }
    e.slip += total.slip;
    e.dashpot += total.dashpot;
    e.bond_break += total.bond_break;
}

// Kinetic energy is set (the spheres' share; clumps add theirs after) only when computed.
inline void book_bodies(EnergyLedger& e, const BodySums& total, bool kinetic) {
    if (kinetic) e.kinetic = total.kinetic;
    e.damping += total.damping;
    e.boundary_work += total.boundary;
    e.body_force_work += total.body;
}

}  // namespace triax
