#pragma once
// Measured laboratory readings in the engine's canonical form: SI units, soil-mechanics
// signs (compression positive, volumetric strain positive = contraction). Parsers of CSV,
// GDS-Lab, AGS4 and JSON uploads (server/io) produce this; comparison and diagnosis use it.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace triax::diagnose {

// Whether a reading's confining pressure is the reference's (Pa): within 2 % of the
// reference (at least 1 Pa's share), the tolerance a lab's cell control holds. The
// diagnosis groups curves by sigma3 through it (plan, residual layout, creep instants).
inline bool same_confining(double confining_pa, double reference_pa) {
    return std::abs(confining_pa - reference_pa) <= 0.02 * std::max(reference_pa, 1.0);
}

enum class CurveKind { Shear, Creep };

// One measured curve. Columns that were not measured are left empty; the others all have
// the same length and are ordered by reading.
struct LabCurve {
    CurveKind kind = CurveKind::Shear;
    int stage = 0;               // creep stage number 1..n (0 for a shear curve)
    double confining_pa = 0.0;   // cell pressure sigma3
    double stress_level = 0.0;   // creep stages: S if known, 0 otherwise
    std::vector<double> time_s;               // time since start of stage
    std::vector<double> axial_strain;         // [-], compression positive
    std::vector<double> axial_deformation_m;  // [m], shortening positive
    std::vector<double> deviator_pa;          // q = sigma1 - sigma3
    std::vector<double> volumetric_strain;    // [-], contraction positive
    std::size_t size() const {
        for (const auto* c : {&time_s, &axial_strain, &axial_deformation_m, &deviator_pa, &volumetric_strain})
            if (!c->empty()) return c->size();
        return 0;
    }
};

// Summary rows (AGS4 TREG/TRET and similar): one per specimen.
struct LabSummaryRow {
    std::string specimen;
    double confining_pa = 0.0;
    double deviator_at_failure_pa = 0.0;
    double strain_at_failure = 0.0;
    double moisture_content = 0.0;   // [-]
    double dry_density_kg_m3 = 0.0;
    double cohesion_pa = 0.0;
    double friction_angle_deg = 0.0;
};

struct LabDataset {
    std::string name;
    std::vector<LabCurve> curves;
    std::vector<LabSummaryRow> summary;
};

}  // namespace triax::diagnose
