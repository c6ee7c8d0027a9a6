#pragma once
// A rigid clump of member spheres (used as loading platens). Members stay ordinary
// entries of ParticleArrays (they take part in contact detection) but are moved
// rigidly from the clump's state; contacts between members of one clump are ignored.
#include "engine/core/types.hpp"

#include <Eigen/Geometry>
#include <vector>

namespace triax {

enum class ClumpControl {
    Free,              // integrated from contact forces + applied_force (+ gravity), with local damping
    VelocityControlled // velocity and angular velocity prescribed by the caller
};

struct Clump {
    std::vector<int> members;
    std::vector<Vec3> body_offsets;     // member centre - centre of mass, in the body frame
    Vec3 position = Vec3::Zero();       // m, centre of mass
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Vec3 velocity = Vec3::Zero();       // m/s
    Vec3 angular_velocity = Vec3::Zero();
    double mass = 0.0;                  // kg, sum of member masses (overlaps not removed)
    Mat3 inertia_body = Mat3::Identity();  // kg m^2 about the centre of mass, body frame
    ClumpControl control = ClumpControl::Free;
    bool fix_rotation = false;          // free clump that translates only (platen)
    Vec3 applied_force = Vec3::Zero();  // N, external load (stress-controlled platen); work is boundary work
    Vec3 applied_torque = Vec3::Zero();
    Vec3 contact_force = Vec3::Zero();  // N, sum of contact forces on the members, last step
    Vec3 contact_torque = Vec3::Zero(); // N m about the centre of mass, last step
};

}  // namespace triax
