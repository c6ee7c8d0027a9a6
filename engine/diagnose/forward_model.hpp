#pragma once
// The model the diagnosis calibrates: a parameter vector in, predicted curves out, at the
// conditions of the lab dataset (same confining pressures, creep stages and load levels).
// The DEM implementation (dem_forward_model.hpp) runs engine/protocol; tests may supply a
// cheap analytic one. simulate() must be deterministic for a given seed and callable from
// several threads at once (the diagnosis runs evaluations concurrently).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnose/effect.hpp"
#include "engine/diagnose/lab_data.hpp"

namespace triax::diagnose {

// A point of the model space: the base parameters plus the physical effects switched on,
// each with its own parameters (ordered as in ForwardModel::effect_parameters).
struct ModelPoint {
    std::vector<double> base;
    std::vector<std::pair<Effect, std::vector<double>>> effects;
};

// A setting of the model that the calibration does not fit (it stays at the scheme's value),
// named in the report so that a user knows what the fit took as given.
struct HeldParameter {
    std::string name;   // e.g. "local_damping"
    std::string unit;   // SI
    double value = 0.0;
    std::string why;    // one phrase
};

class ForwardModel {
public:
    virtual ~ForwardModel() = default;
    // Parameters calibrated in every model (stiffness, friction, bond strength, creep law).
    virtual std::vector<ParameterSpec> base_parameters() const = 0;
    // Parameters of a physical effect; empty if the model cannot represent it (it is then
    // skipped). Never called for test artefacts.
    virtual std::vector<ParameterSpec> effect_parameters(Effect e) const = 0;
    // Effects the model already contains (switched on in its scheme): not proposed again.
    virtual bool includes(Effect) const { return false; }
    // Why effect e is not offered on these data (it is part of the base, or the data cannot
    // show it): one phrase for the report; empty when it is offered.
    virtual std::string not_offered_reason(Effect) const { return {}; }
    // Settings the calibration holds at the scheme's values.
    virtual std::vector<HeldParameter> held_fixed() const { return {}; }
    // Height of the specimen whose deformations simulate() reports (m): a seating strain
    // adds strain x height to them (test_artefacts.hpp).
    virtual double specimen_height_m() const { return 0.2; }
    // Predicted curves, one per lab curve it can reproduce, identified by (kind, stage,
    // confining_pa) like the lab's. Shear curves: axial_strain, deviator_pa,
    // volumetric_strain. Creep curves: time_s, axial_strain (and axial_deformation_m).
    // Throws on failure; the diagnosis records the failure and scores the point as bad.
    virtual LabDataset simulate(const ModelPoint& point, std::uint64_t seed) const = 0;
};

}  // namespace triax::diagnose
