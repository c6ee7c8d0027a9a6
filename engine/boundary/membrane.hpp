#pragma once
// Flexible membrane of the paper (Fig. 3B): one layer of equal spheres on a cylindrical
// lattice (n_theta around, n_z along the axis) joined to their 4 lattice neighbours by
// contact bonds, which carry force but no moment. The confining pressure acts as follower
// forces: each membrane sphere receives F = p * A_trib * n, with n the inward normal of the
// *deformed* local surface and A_trib its tributary area, both from the cross product of
// the lattice diagonals (t_theta x t_z)/4 (central differences), so bulging and shear
// bands stay free. Axis = z, specimen centred at the origin. SI units.
#include <vector>

#include "engine/core/world.hpp"

namespace triax::boundary {

class Membrane {
public:
    // Adds the spheres to `world` in group `group`. The inner envelope of the membrane
    // (centres minus r) is at radius specimen_radius_m; rows span the specimen height.
    Membrane(World& world, double specimen_radius_m, double height_m, double particle_radius_m, double density,
             int group);

    // Installs the lattice bonds (call once, after the spheres are placed).
    void bond(World& world, double strength_n);

    // Sets the external force of each membrane sphere from the pressure (Pa) on the
    // current geometry. Returns the total radial force magnitude applied (N).
    double apply_pressure(World& world, double pressure_pa) const;

    // Volume enclosed by the inner envelope between z_bottom and z_top (m^3): the inner
    // cross-section of each row (shoelace on the ring, shrunk by r) integrated over z, the
    // end rows extended to the platens.
    double enclosed_volume(const World& world, double z_bottom, double z_top) const;

    // Mean inner radius of the ring (m).
    double mean_inner_radius(const World& world) const;

    // Holds every membrane sphere fixed (generation) or frees them.
    void set_fixed(World& world, bool fixed) const;

    int n_theta() const { return n_theta_; }
    int n_z() const { return n_z_; }
    int count() const { return n_theta_ * n_z_; }
    double particle_radius() const { return r_; }
    int first_index() const { return first_; }
    int index(int it, int iz) const { return first_ + iz * n_theta_ + ((it % n_theta_) + n_theta_) % n_theta_; }

private:
    int first_ = 0;
    int n_theta_ = 0, n_z_ = 0;
    double r_ = 0.0;
    double z0_ = 0.0, dz_ = 0.0;
};

}  // namespace triax::boundary
