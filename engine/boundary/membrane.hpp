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

// Largest ratio of the smallest grain's radius to a chosen membrane sphere radius that the
// lattice holds: 1.2 (the browser test's specimen) and 1.28 (preset B at 150 grains with 6 mm
// spheres) consolidated; 1.54 (5 mm spheres) lost a grain out of the domain after 297k steps.
inline constexpr double kMaxGrainToMembraneRadius = 1.35;

// The ratio the automatic rule keeps below: the largest one seen to hold, 1.2.
inline constexpr double kAutomaticGrainToMembraneRadius = 1.2;

// The membrane sphere radius a scheme gets when it leaves it at 0 (Specimen,
// specimen_budget, run_estimate use this one rule): a quarter of the mean grain radius but
// not below the smallest grain, 1 mm .. D/20 (a few thousand spheres), and never so small
// that the smallest grain is more than 1.2 times a membrane sphere. Without the last clause
// preset B reduced to 150 grains (radii 7.7-15.4 mm) got 5 mm spheres (D/20), never met the
// consolidation criterion and lost a grain; it takes 6.4 mm spheres now.
inline double automatic_membrane_radius(double grain_r_min_m, double grain_r_mean_m, double specimen_diameter_m) {
    const double r = grain_r_min_m > 0.25 * grain_r_mean_m ? grain_r_min_m : 0.25 * grain_r_mean_m;
    const double lo = 1.0e-3, hi = 0.05 * specimen_diameter_m;
    const double clamped = r < lo ? lo : (r > hi ? hi : r);
    const double holds = grain_r_min_m / kAutomaticGrainToMembraneRadius;
    return clamped > holds ? clamped : holds;
}

class Membrane {
public:
    // Adds the spheres to `world` in group `group`. The inner envelope of the membrane
    // (centres minus r) is at radius specimen_radius_m; rows span the specimen height,
    // centred at z = centre_z_m (an imported specimen's platens need not be symmetric).
    Membrane(World& world, double specimen_radius_m, double height_m, double particle_radius_m, double density,
             int group, double centre_z_m = 0.0);

    // The number of spheres of the lattice the constructor builds for these dimensions.
    static int lattice_count(double specimen_radius_m, double height_m, double particle_radius_m);

    // Installs the lattice bonds (call once, after the spheres are placed).
    void bond(World& world, double strength_n);

    // Moves the spheres to the positions of an exported state of this lattice (m, in
    // index order; count() of them), after bond(): the bonds keep the lattice's rest
    // lengths, so a stretched membrane carries on stretched. Throws InputError on a wrong count.
    void restore(World& world, const std::vector<Vec3>& positions) const;

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
