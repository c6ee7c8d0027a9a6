#pragma once
// Basic vocabulary of the engine: vector aliases and the two error types.
// SI units everywhere inside the engine (m, kg, s, N, J).
#include <Eigen/Dense>
#include <stdexcept>
#include <string>

namespace triax {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Bad input from the caller (a negative radius, an unknown index, ...). The message
// names the argument at fault and why.
class InputError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// The simulation became unphysical (NaN, exploding kinetic energy, a particle
// leaving the domain). Carries the step at which it was detected and the cause.
class SimulationError : public std::runtime_error {
public:
    SimulationError(long step, const std::string& cause)
        : std::runtime_error("simulation error at step " + std::to_string(step) + ": " + cause),
          step_(step), cause_(cause) {}
    long step() const noexcept { return step_; }
    const std::string& cause() const noexcept { return cause_; }

private:
    long step_;
    std::string cause_;
};

}  // namespace triax
