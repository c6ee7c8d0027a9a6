#pragma once
// Four consecutive free spheres integrated at once, across SIMD lanes: SphereIntegrator
// (central_difference.hpp) lane by lane.
//
// Every lane performs the scalar integrator's operations in its order (Eigen's
// (x x + y y) + z z for dots, local damping's (alpha |F|) sign(v), no FMA contraction:
// sphere_lanes.cpp is built with -ffp-contract=off), and the block's sums take the four
// particles' terms one after the other in particle order, so a particle gets the bits the
// scalar integrator gives it. Compiled for AVX2 and called only where the CPU has it
// (simd::avx2_available).
#include "engine/core/particle_arrays.hpp"
#include "engine/energy/step_sums.hpp"
#include "engine/integrate/central_difference.hpp"

#include <vector>

namespace triax {

// Particles p .. p+3 from their gathered contact forces, torques (N, N m) and stiffness
// sums: when none of the four is prescribed or a clump member, integrates them as
// SphereIntegrator would, one after the other, and returns true; otherwise writes nothing
// and returns false (the caller runs the four through SphereIntegrator).
bool integrate_sphere_lanes(const SphereIntegrator& in, long p, const Vec3* f_contact, const Vec3* t,
                            const double* kt, const double* kr, ParticleArrays& pa,
                            std::vector<double>& inertial_mass, std::vector<double>& inertial_inertia, BodySums& s);

}  // namespace triax
