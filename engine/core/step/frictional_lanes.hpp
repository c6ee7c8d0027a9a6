#pragma once
// Four touching slots of the plain frictional law at once (the linear law of an unbonded
// contact without dashpot or rolling resistance: the diagnosis's forward runs and the
// cohesionless packings), across SIMD lanes: the pair kinematics, the shear history's turn
// into the new contact plane, the Coulomb slider and the slot's force and torques.
//
// Every lane performs the scalar path's operations in the scalar path's order (Eigen's
// (x x + y y) + z z for dots and norms, the same cross products, the same +0 of the absent
// dashpot and moment, no FMA contraction: frictional_lanes.cpp is built with
// -ffp-contract=off), so a slot gets the bits that ContactForces::touching_slot gives it and
// trajectories do not depend on which path ran. Four independent slots in one instruction
// stream shorten the time per slot: one slot's chain (sqrt, divisions, the rotation's
// sqrt) no longer waits alone. The kernel is compiled for AVX2 and runs only on CPUs that
// have it (simd::avx2_available); elsewhere the scalar path runs, with the same bits.
#include "engine/contact/contact_store.hpp"
#include "engine/contact/linear.hpp"
#include "engine/core/particle_arrays.hpp"
#include "engine/core/simd/avx2.hpp"
#include "engine/energy/step_sums.hpp"

namespace triax::step {

using simd::kLaneCount;

// Call only where simd::avx2_available(). Slots k[0..3] (distinct, touching by the screen,
// in slot order): when all four are unbonded, their laws have no dashpot and their effective
// overlaps are positive, writes the four slots as touching_slot would, adds their energies
// (slip, and the springs' stored energy when `state_energy`) to `sums` as four
// ContactSums::add calls would, and returns true; otherwise writes nothing and returns false
// (the caller runs the four through the scalar path).
bool frictional_lanes(ContactStore& c, const ParticleArrays& pa, const LinearContact::Params* params, double dt,
                      const long* k, bool state_energy, ContactSums& sums);

}  // namespace triax::step
