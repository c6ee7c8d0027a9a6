#pragma once
// Energy partitions as in PFC (J). State quantities (strain, bond strain, kinetic) are
// those of the last step of the last World::cycle() call (computed on that step only: the
// ledger cannot be read in between; kinetic on every step when a kinetic-energy limit is
// set); dissipations and works accumulate every step from the World's creation (or the
// last reset()).
//
// Balance: boundary_work + body_force_work
//        = strain + bond_strain + kinetic + slip + damping + dashpot + bond_break + creep
//          + breakage
// (up to the O(dt) error of the central-difference integration).
namespace triax {

struct EnergyLedger {
    // State.
    double strain = 0.0;        // springs of unbonded contacts: 0.5 Fn^2/kn + 0.5 |Fs|^2/ks (+ rolling 0.5 M^2/kr)
    double bond_strain = 0.0;   // the same for bonded contacts (contact bonds)
    double kinetic = 0.0;       // 0.5 m v^2 + 0.5 I w^2 (inertial masses; clumps as rigid bodies)
    // Accumulated dissipation.
    double slip = 0.0;          // friction slider (and rolling slider)
    double damping = 0.0;       // PFC local damping
    double dashpot = 0.0;       // viscous normal dashpots
    double bond_break = 0.0;    // spring energy released when a bond breaks in tension
    double creep = 0.0;         // added by the time-dependent contact mechanism (engine/creep)
    double breakage = 0.0;      // spring energy released by crushing contacts (engine/contact/grain_crushing.hpp)
    // Accumulated input.
    double boundary_work = 0.0; // walls, velocity-controlled/loaded clumps, applied particle forces
    double body_force_work = 0.0;  // gravity

    double stored() const { return strain + bond_strain + kinetic; }
    double dissipated() const { return slip + damping + dashpot + bond_break + creep + breakage; }
    double input() const { return boundary_work + body_force_work; }
    // input - stored - dissipated; ~0 when the books close.
    double imbalance() const { return input() - stored() - dissipated(); }

    void reset_accumulated() {
        slip = damping = dashpot = bond_break = creep = breakage = 0.0;
        boundary_work = body_force_work = 0.0;
    }
};

}  // namespace triax
