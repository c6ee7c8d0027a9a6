#pragma once
// The integrator for spheres: central difference (velocities at half steps) with PFC
// local damping (local_damping.hpp), per particle, after its contact forces are gathered.
//
//   F = F_contact + F_ext + m g,   F_d = F - alpha |F| sign(v)   (componentwise)
//   v' = v + F_d dt / m_in,   w' = w + T_d dt / I_in,   x' = x + v' dt
// m_in, I_in: the inertial mass and inertia, raised to 4 k dt^2 by density scaling
// (k: the gathered stiffness sums). Energies of the step (J) go into the block's
// BodySums: damping (F - F_d) . v_mid dt, applied force F_ext . v_mid dt (boundary work),
// gravity m g . v_mid dt (true mass), kinetic 0.5 m_in v'^2 + 0.5 I_in w'^2 when asked.
// Prescribed particles (kFixedVelocity) only move; what their contacts push against is
// boundary work. Clump members are left to their clump.
//
// Checks (the first failing particle of a block is kept): non-finite velocity or spin,
// a step longer than the radius, leaving the domain box.
#include "engine/core/particle_arrays.hpp"
#include "engine/energy/step_sums.hpp"
#include "engine/integrate/local_damping.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace triax {

struct SphereIntegrator {
    double dt;                 // s
    double alpha;              // local damping coefficient
    Vec3 gravity;              // m/s^2
    bool density_scaling;
    bool kinetic;              // compute the kinetic energy this step
    bool has_domain;
    Vec3 lo, hi;               // m, domain box (when has_domain)

    // Integrates particle p from its gathered contact force and torque (N, N m) and
    // stiffness sums. Returns false for clump members (not moved here).
    [[gnu::always_inline]] inline bool operator()(long p, const Vec3& f_contact, const Vec3& t, double kt, double kr,
                                                  ParticleArrays& pa, std::vector<double>& inertial_mass,
                                                  std::vector<double>& inertial_inertia, BodySums& s) const {
        const Vec3 f = f_contact + (pa.external_force[p] + pa.mass[p] * gravity);
        pa.force[p] = f;
        pa.torque[p] = t;
        const std::uint8_t flags = pa.flags[p];
        if (flags & kClumpMember) return false;
        if (flags & kFixedVelocity) {
            s.boundary += -f_contact.dot(pa.velocity[p]) * dt - t.dot(pa.angular_velocity[p]) * dt;
            pa.position[p] += pa.velocity[p] * dt;
        } else {
            double m = pa.mass[p], inertia = pa.inertia[p];
            if (density_scaling) {
                m = std::max(m, 4.0 * kt * dt * dt);
                inertia = std::max(inertia, 4.0 * kr * dt * dt);
            }
            inertial_mass[p] = m;
            inertial_inertia[p] = inertia;
            const Vec3 v_old = pa.velocity[p], w_old = pa.angular_velocity[p];
            const Vec3 fd = local_damping_force(f, v_old, alpha);
            const Vec3 td = local_damping_force(t, w_old, alpha);
            const Vec3 v_new = v_old + fd * (dt / m);
            const Vec3 w_new = w_old + td * (dt / inertia);
            const Vec3 v_mid = 0.5 * (v_old + v_new), w_mid = 0.5 * (w_old + w_new);
            s.damping += ((f - fd).dot(v_mid) + (t - td).dot(w_mid)) * dt;
            s.boundary += pa.external_force[p].dot(v_mid) * dt;
            s.body += pa.mass[p] * gravity.dot(v_mid) * dt;
            if (kinetic) s.kinetic += 0.5 * m * v_new.squaredNorm() + 0.5 * inertia * w_new.squaredNorm();
            pa.velocity[p] = v_new;
            pa.angular_velocity[p] = w_new;
            pa.position[p] += v_new * dt;
            check_step_length(p, v_new, w_new, pa.radius[p], s);
        }
        check_domain(p, pa, s);
        return true;
    }

    // "Left the domain box", when one is set; the block keeps its first failing particle.
    [[gnu::always_inline]] inline void check_domain(long p, const ParticleArrays& pa, BodySums& s) const {
        if (has_domain && s.unstable < 0 &&
            ((pa.position[p].array() < lo.array()).any() || (pa.position[p].array() > hi.array()).any())) {
            s.unstable = p;
            s.cause = Instability::left_domain;
        }
    }

    // "Moved more than its radius in one step", without a sqrt per particle: |v| dt is far
    // below the radius when |v|^2 dt^2 < r^2 (1 - 2^-40) (rounding: < 1e-15 relative), and
    // then the exact check cannot fire; non-finite values fail the screen and are checked.
    static constexpr double kStableBelow = 1.0 - 0x1p-40;
    [[gnu::always_inline]] inline void check_step_length(long p, const Vec3& v_new, const Vec3& w_new, double r,
                                                         BodySums& s) const {
        const double v2 = v_new.squaredNorm();
        if (s.unstable < 0 && !(v2 * (dt * dt) < r * r * kStableBelow && std::isfinite(w_new.squaredNorm()))) {
            const double step_len = std::sqrt(v2) * dt;
            if (!std::isfinite(step_len) || !std::isfinite(w_new.squaredNorm())) {
                s.unstable = p;
                s.cause = Instability::non_finite_velocity;
            } else if (step_len > r) {
                s.unstable = p;
                s.cause = Instability::faster_than_radius;
            }
        }
    }
};

// The SimulationError text for particle p's failed check.
inline std::string describe_instability(Instability cause, long p, const ParticleArrays& pa, double dt) {
    std::ostringstream why;
    if (cause == Instability::non_finite_velocity) why << "non-finite velocity (NaN) of particle " << p;
    else if (cause == Instability::faster_than_radius)
        why << "exploding kinetic energy: particle " << p << " moved " << pa.velocity[p].norm() * dt
            << " m in one step, more than its radius " << pa.radius[p] << " m (time step too large or overlap too deep)";
    else
        why << "particle " << p << " escaped the domain box at (" << pa.position[p].x() << ", " << pa.position[p].y()
            << ", " << pa.position[p].z() << ") m";
    return why.str();
}

}  // namespace triax
