#pragma once
// Contact forces between spheres and the rigid walls (planes, cylinders), over the same
// contact-law evaluator as the ball-ball loop (contact_forces.hpp). Wall slots are few:
// one thread runs them in slot order, beside the ball-ball blocks (it touches only wall
// slots and walls, and reads particles). It also gives the walls their forces.
//
// Sign conventions: n points from the wall into the particle; the law's force acts on the
// particle; PlaneWall::force / CylinderWall::force are the reaction, by the particles on
// the wall (N); CylinderWall::radial_force sums the normal force magnitudes (N).
#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"
#include "engine/core/walls.hpp"
#include "engine/energy/step_sums.hpp"

#include <cstddef>
#include <vector>

namespace triax::step {

template <class Evaluator>
struct WallContactForces {
    using Params = typename Evaluator::Params;

    // All wall slots; the springs' stored energy is computed on every step (few contacts).
    static ContactSums all(WallContactStore& wc, std::vector<PlaneWall>& planes, std::vector<CylinderWall>& cylinders,
                           const ParticleArrays& pa, const std::vector<Params>& params, double dt, bool rolling) {
        for (auto& w : planes) { w.force.setZero(); w.contact_count = 0; }
        for (auto& w : cylinders) { w.force.setZero(); w.radial_force = 0.0; w.contact_count = 0; }
        return rolling ? all<true>(wc, planes, cylinders, pa, params, dt) : all<false>(wc, planes, cylinders, pa, params, dt);
    }

private:
    template <bool kRolling>
    static ContactSums all(WallContactStore& wc, std::vector<PlaneWall>& planes, std::vector<CylinderWall>& cylinders,
                           const ParticleArrays& pa, const std::vector<Params>& params, double dt) {
        ContactSums total;
        for (std::size_t k = 0; k < wc.size(); ++k) {
            const int p = wc.particle[k];
            const Vec3& x = pa.position[p];
            const double r = pa.radius[p];
            Vec3 n;           // wall -> particle
            double dist;      // m, centre to wall surface
            Vec3 v_wall;      // m/s, wall surface velocity at the particle
            bool in_range = true;
            if (wc.wall_kind[k] == 0) {
                const PlaneWall& w = planes[wc.wall[k]];
                n = w.normal;
                dist = (x - w.point).dot(n);
                v_wall = w.velocity;
            } else {
                const CylinderWall& w = cylinders[wc.wall[k]];
                const Vec3 rel = x - w.base;
                const double a = rel.dot(w.axis);
                const Vec3 radial = rel - a * w.axis;
                const double rho = radial.norm();
                in_range = a >= 0.0 && a <= w.height && rho > 0.0;
                const Vec3 e = rho > 0 ? Vec3(radial / rho) : Vec3::UnitX();
                n = -e;
                dist = w.radius - rho;
                v_wall = w.velocity + w.radial_velocity * e;
            }
            const double overlap = r - dist;
            wc.overlap[k] = overlap;
            if (!in_range || overlap <= 0.0) {
                if (wc.active[k]) wc.reset_history(k);
                wc.force_on_particle[k].setZero();
                wc.torque_on_particle[k].setZero();
                continue;
            }
            // PFC places the contact point in the middle of the overlap.
            const Vec3 xc = x - n * (dist + 0.5 * (r - dist));
            const Vec3 arm = xc - x;
            typename Evaluator::Kinematics kin;
            kin.n = n;
            kin.overlap = overlap;
            kin.v_rel = pa.velocity[p] + pa.angular_velocity[p].cross(arm) - v_wall;
            kin.w_rel = pa.angular_velocity[p];
            kin.m_eff = pa.mass[p];
            kin.r_bar = r;
            kin.dt = dt;
            Vec3 no_moment = Vec3::Zero();
            typename Evaluator::History h{wc.normal_force[k], wc.shear_force[k], no_moment, nullptr, nullptr, 0.0, 0.0, 0.0};
            const typename Evaluator::Outcome o = Evaluator::template evaluate<kRolling>(params[wc.law[k]], kin, h);
            total.add(o);
            wc.active[k] = 1;
            wc.contact_point[k] = xc;
            wc.force_on_particle[k] = o.force;
            wc.torque_on_particle[k] = arm.cross(o.force) + o.moment;
            if (wc.wall_kind[k] == 0) {
                PlaneWall& w = planes[wc.wall[k]];
                w.force -= o.force;
                ++w.contact_count;
            } else {
                CylinderWall& w = cylinders[wc.wall[k]];
                w.force -= o.force;
                w.radial_force += wc.normal_force[k];
                ++w.contact_count;
            }
        }
        return total;
    }
};

}  // namespace triax::step
