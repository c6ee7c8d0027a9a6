#pragma once
// MeasurementSphere (PFC "measure" logic in 3-D): a fixed sphere in space where the
// engine reports, on request, porosity, coordination number, mean displacement since
// a reference snapshot, mean angular velocity and the average stress tensor.
//
// Porosity: 1 - (sum of exact sphere-sphere intersection volumes of every particle with
// the measurement sphere) / (measurement volume). Overlaps between particles are not
// subtracted (they are small in a DEM packing; PFC does the same).
// Coordination: mean number of active contacts (ball and wall) of the particles whose
// centres are inside.
// Stress (Pa, compression positive):
//   sigma = -(1 - n) / (sum V_p) * sum_{p inside} sum_{c of p} sym((x_c - x_p) (x) F_c,p)
// the PFC form, where F_c,p is the contact force on p; (1 - n)/sum V_p converts the sum
// over particles with their centre inside into a stress for the measurement volume.
// Displacement: mean of (x - x_ref) over the particles inside at reference time.
// Angular velocity: mean spin (rad/s, signed, per axis; right-handed = counter-clockwise
// seen from +axis, as in PFC) over the particles inside now.
#include "engine/core/types.hpp"
#include "engine/core/world.hpp"

#include <vector>

namespace triax {

struct MeasurementReading {
    double porosity = 0.0;
    double coordination = 0.0;
    Vec3 mean_displacement = Vec3::Zero();        // m
    Vec3 mean_angular_velocity = Vec3::Zero();    // rad/s
    Mat3 stress = Mat3::Zero();                   // Pa, compression positive
    int particle_count = 0;                       // centres inside now
};

class MeasurementSphere {
public:
    MeasurementSphere(const Vec3& center, double radius);

    // Remembers the current positions of the particles inside as the displacement origin.
    void set_reference(const World& world);
    MeasurementReading measure(const World& world) const;

    const Vec3& center() const { return center_; }
    double radius() const { return radius_; }
    double volume() const;

    // Volume (m^3) of the intersection of two spheres (radii r1, r2, centres d apart).
    static double intersection_volume(double r1, double r2, double d);

private:
    Vec3 center_;
    double radius_;
    std::vector<int> reference_members_;
    std::vector<Vec3> reference_positions_;
};

}  // namespace triax
