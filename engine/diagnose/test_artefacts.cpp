// Seating error and membrane compliance applied to predicted curves (see test_artefacts.hpp).
#include "engine/diagnose/test_artefacts.hpp"

#include <stdexcept>
#include <string>

namespace triax::diagnose {

namespace {

void apply_seating(LabDataset& d, double s, double height_m) {
    int first_stage = 1 << 30;
    for (const auto& c : d.curves)
        if (c.kind == CurveKind::Creep) first_stage = std::min(first_stage, c.stage);
    for (auto& c : d.curves) {
        if (c.kind == CurveKind::Shear) {
            if (c.axial_strain.empty()) continue;
            // Shift the curve right by s and prepend the unloaded closure branch (0 -> s at q = 0).
            for (auto& e : c.axial_strain) e += s;
            for (auto& u : c.axial_deformation_m) u += s * height_m;
            if (s > 0.0) {
                c.axial_strain.insert(c.axial_strain.begin(), 0.0);
                if (!c.axial_deformation_m.empty()) c.axial_deformation_m.insert(c.axial_deformation_m.begin(), 0.0);
                if (!c.deviator_pa.empty()) c.deviator_pa.insert(c.deviator_pa.begin(), c.deviator_pa.front());
                if (!c.volumetric_strain.empty())
                    c.volumetric_strain.insert(c.volumetric_strain.begin(), c.volumetric_strain.front());
                if (!c.time_s.empty()) c.time_s.insert(c.time_s.begin(), c.time_s.front());
            }
        } else if (c.stage == first_stage) {
            for (auto& e : c.axial_strain) e += s;
            for (auto& u : c.axial_deformation_m) u += s * height_m;
        }
    }
}

void apply_membrane(LabDataset& d, double k_m) {
    for (auto& c : d.curves) {
        if (c.kind != CurveKind::Shear || c.deviator_pa.size() != c.axial_strain.size()) continue;
        for (std::size_t i = 0; i < c.deviator_pa.size(); ++i) c.deviator_pa[i] += k_m * c.axial_strain[i];
    }
}

}  // namespace

void apply_test_artefact(LabDataset& predicted, Effect e, const std::vector<double>& p, double specimen_height_m) {
    if (!is_test_artefact(e))
        throw std::invalid_argument("apply_test_artefact: '" + std::string(effect_name(e)) + "' is not a test artefact");
    if (p.size() != 1)
        throw std::invalid_argument("apply_test_artefact: '" + std::string(effect_name(e)) + "' takes 1 parameter, got " +
                                    std::to_string(p.size()));
    if (e == Effect::SeatingError) apply_seating(predicted, p[0], specimen_height_m);
    else apply_membrane(predicted, p[0]);
}

}  // namespace triax::diagnose
