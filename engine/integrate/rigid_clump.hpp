#pragma once
// The integrator for clumps (rigid bodies of member spheres): member forces and moments
// summed about the centre of mass, then central difference with PFC local damping, as for
// spheres (central_difference.hpp), with the full inertia tensor rotated to the world frame
// (gyroscopic term neglected, PFC's clump update at low spin).
//
//   F = sum F_member (contacts + applied + gravity) + applied_force
//   T = sum (x_member - x_c) x F_member + T_member + applied_torque
// A velocity-controlled clump keeps its velocity; what its contacts push against is
// boundary work. Energies (J) are booked only when `books` is given. The caller places the
// members from the clump's new state (World::update_clump_members).
#include "engine/core/clump.hpp"
#include "engine/core/particle_arrays.hpp"
#include "engine/energy/energy_ledger.hpp"
#include "engine/integrate/local_damping.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <vector>

namespace triax {

struct ClumpIntegrator {
    double dt;                 // s
    double alpha;              // local damping coefficient
    Vec3 gravity;              // m/s^2
    bool density_scaling;
    bool kinetic;              // add the clump's kinetic energy this step
    // Stiffness sums of each member's contacts (the gather's, N/m and N m).
    const std::vector<double>& stiffness_sum;
    const std::vector<double>& rot_stiffness_sum;

    void operator()(Clump& c, const ParticleArrays& pa, EnergyLedger* books) const {
        Vec3 f = Vec3::Zero(), t = Vec3::Zero(), f_ext = Vec3::Zero(), f_contact = Vec3::Zero(), t_contact = Vec3::Zero();
        double kt = 0.0, kr = 0.0;
        for (int p : c.members) {
            const Vec3 arm = pa.position[p] - c.position;
            f += pa.force[p];
            t += arm.cross(pa.force[p]) + pa.torque[p];
            const Vec3 fc = pa.force[p] - pa.external_force[p] - pa.mass[p] * gravity;
            f_contact += fc;
            t_contact += arm.cross(fc) + pa.torque[p];
            f_ext += pa.external_force[p];
            kt += stiffness_sum[p];
            kr += rot_stiffness_sum[p] + stiffness_sum[p] * arm.squaredNorm();
        }
        c.contact_force = f_contact;
        c.contact_torque = t_contact;
        if (c.control == ClumpControl::VelocityControlled) {
            if (books) books->boundary_work += -(f_contact.dot(c.velocity) + t_contact.dot(c.angular_velocity)) * dt;
        } else {
            f += c.applied_force;
            t += c.applied_torque;
            double m = c.mass;
            const Mat3 rot = c.orientation.toRotationMatrix();
            Mat3 inertia = rot * c.inertia_body * rot.transpose();
            if (density_scaling) {
                m = std::max(m, 4.0 * kt * dt * dt);
                const double i_min = 4.0 * kr * dt * dt;
                for (int a = 0; a < 3; ++a) inertia(a, a) = std::max(inertia(a, a), i_min);
            }
            const Vec3 v_old = c.velocity, w_old = c.angular_velocity;
            const Vec3 fd = local_damping_force(f, v_old, alpha);
            const Vec3 v_new = v_old + fd * (dt / m);
            Vec3 w_new = Vec3::Zero();
            Vec3 td = Vec3::Zero();
            if (!c.fix_rotation) {
                td = local_damping_force(t, w_old, alpha);
                w_new = w_old + inertia.ldlt().solve(td) * dt;
            }
            const Vec3 v_mid = 0.5 * (v_old + v_new), w_mid = 0.5 * (w_old + w_new);
            if (books) {
                books->damping += (f - fd).dot(v_mid) * dt + (c.fix_rotation ? 0.0 : (t - td).dot(w_mid) * dt);
                books->boundary_work += (c.applied_force + f_ext).dot(v_mid) * dt + c.applied_torque.dot(w_mid) * dt;
                books->body_force_work += c.mass * gravity.dot(v_mid) * dt;
                if (kinetic) books->kinetic += 0.5 * m * v_new.squaredNorm() + 0.5 * w_new.dot(inertia * w_new);
            }
            c.velocity = v_new;
            c.angular_velocity = w_new;
        }
        c.position += c.velocity * dt;
        const double w = c.angular_velocity.norm();
        if (w > 0) {
            const Eigen::Quaterniond dq(Eigen::AngleAxisd(w * dt, c.angular_velocity / w));
            c.orientation = (dq * c.orientation).normalized();
        }
    }
};

}  // namespace triax
