#include "engine/boundary/membrane.hpp"

#include <cmath>

namespace triax::boundary {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Touching neighbours around the ring and along the axis (spacing 2 r).
int ring_count(double specimen_radius_m, double r) {
    return std::max(8, static_cast<int>(std::round(kPi / std::asin(std::min(1.0, r / (specimen_radius_m + r))))));
}
int row_count(double height_m, double r) { return std::max(3, static_cast<int>(std::floor(height_m / (2.0 * r)))); }
}  // namespace

int Membrane::lattice_count(double specimen_radius_m, double height_m, double particle_radius_m) {
    return ring_count(specimen_radius_m, particle_radius_m) * row_count(height_m, particle_radius_m);
}

Membrane::Membrane(World& world, double specimen_radius_m, double height_m, double particle_radius_m, double density,
                   int group, double centre_z_m)
    : r_(particle_radius_m) {
    if (!(particle_radius_m > 0.0)) throw InputError("membrane: particle radius must be > 0");
    const double rc = specimen_radius_m + r_;
    n_theta_ = ring_count(specimen_radius_m, r_);
    n_z_ = row_count(height_m, r_);
    dz_ = (height_m - 2.0 * r_) / (n_z_ - 1);
    z0_ = centre_z_m - 0.5 * height_m + r_;
    first_ = static_cast<int>(world.particle_count());
    for (int iz = 0; iz < n_z_; ++iz) {
        for (int it = 0; it < n_theta_; ++it) {
            const double th = 2.0 * kPi * (it + 0.5 * (iz % 2)) / n_theta_;
            world.add_sphere(Vec3(rc * std::cos(th), rc * std::sin(th), z0_ + iz * dz_), r_, density, group);
        }
    }
}

void Membrane::bond(World& world, double strength_n) {
    // Ring neighbours touch (gap 0) and axial neighbours are dz - 2r apart; staggered rows
    // make the axial neighbours the two nearest spheres of the next row.
    auto& p = world.particles();
    const double dth = std::hypot(p.position[index(0, 0)].x() - p.position[index(1, 0)].x(),
                                  p.position[index(0, 0)].y() - p.position[index(1, 0)].y());
    const double diag = std::hypot(0.5 * dth, dz_);
    const double tol = std::max(dth, diag) - 2.0 * r_ + 0.05 * r_;
    world.bond_contacts(p.group[first_], p.group[first_], std::max(0.0, tol), strength_n, strength_n);
}

void Membrane::restore(World& world, const std::vector<Vec3>& positions) const {
    if (static_cast<int>(positions.size()) != count())
        throw InputError("membrane: " + std::to_string(positions.size()) + " positions for a lattice of " +
                         std::to_string(count()) + " spheres");
    auto& p = world.particles();
    for (int k = 0; k < count(); ++k) p.position[first_ + k] = positions[k];
    world.invalidate_neighbors();
}

double Membrane::apply_pressure(World& world, double pressure_pa) const {
    auto& p = world.particles();
    double total = 0.0;
    for (int iz = 0; iz < n_z_; ++iz) {
        for (int it = 0; it < n_theta_; ++it) {
            const int k = index(it, iz);
            const Vec3 t_theta = p.position[index(it + 1, iz)] - p.position[index(it - 1, iz)];
            // Axial tangent: neighbours in the rows above/below (one-sided at the ends).
            const int up = std::min(iz + 1, n_z_ - 1), dn = std::max(iz - 1, 0);
            const Vec3 t_z = p.position[index(it, up)] - p.position[index(it, dn)];
            Vec3 a = t_theta.cross(t_z);  // outward for counter-clockwise theta and +z
            // Central differences span two spacings each way; one-sided ends span one.
            const double span = (up - dn == 2) ? 4.0 : 2.0;
            a /= span;
            // The ring is on the outside: push inwards (towards the axis).
            const Vec3 radial(p.position[k].x(), p.position[k].y(), 0.0);
            if (a.dot(radial) < 0.0) a = -a;
            // End rows carry half a row of membrane above/below them beyond the last row.
            p.external_force[k] = -pressure_pa * a;
            total += pressure_pa * a.norm();
        }
    }
    return total;
}

double Membrane::enclosed_volume(const World& world, double z_bottom, double z_top) const {
    const auto& p = world.particles();
    std::vector<double> area(n_z_), z(n_z_);
    for (int iz = 0; iz < n_z_; ++iz) {
        double a2 = 0.0, zm = 0.0, rsum = 0.0;
        for (int it = 0; it < n_theta_; ++it) {
            const Vec3& q0 = p.position[index(it, iz)];
            const Vec3& q1 = p.position[index(it + 1, iz)];
            a2 += q0.x() * q1.y() - q1.x() * q0.y();
            zm += q0.z();
            rsum += std::hypot(q0.x(), q0.y());
        }
        const double rc = rsum / n_theta_;
        const double a_centres = 0.5 * std::abs(a2);
        // Inner envelope: the centre polygon shrunk by one membrane radius.
        const double scale = (rc - r_) / rc;
        area[iz] = a_centres * scale * scale;
        z[iz] = zm / n_theta_;
    }
    double v = 0.0;
    for (int iz = 0; iz + 1 < n_z_; ++iz) v += 0.5 * (area[iz] + area[iz + 1]) * (z[iz + 1] - z[iz]);
    v += area.front() * std::max(0.0, z.front() - z_bottom);
    v += area.back() * std::max(0.0, z_top - z.back());
    return v;
}

double Membrane::mean_inner_radius(const World& world) const {
    const auto& p = world.particles();
    double s = 0.0;
    for (int k = first_; k < first_ + count(); ++k) s += std::hypot(p.position[k].x(), p.position[k].y());
    return s / count() - r_;
}

void Membrane::set_fixed(World& world, bool fixed) const {
    auto& p = world.particles();
    for (int k = first_; k < first_ + count(); ++k) {
        if (fixed) {
            p.flags[k] |= kFixedVelocity;
            p.velocity[k].setZero();
            p.angular_velocity[k].setZero();
        } else {
            p.flags[k] &= static_cast<std::uint8_t>(~kFixedVelocity);
        }
    }
}

}  // namespace triax::boundary
