#pragma once
// Column vocabulary shared by the CSV and JSON lab parsers: a column name is a quantity
// plus a unit suffix (q_kPa, time_min, axial_strain_pct, ...). Values are converted to SI
// on the way in; lab_dataset_to_json writes them back in the canonical lab unit.
#include "engine/diagnose/lab_data.hpp"

#include <optional>
#include <string>
#include <vector>

namespace triax::io {

enum class LabQuantity { Kind, Stage, Confining, StressLevel, Time, AxialStrain, AxialDeformation, Deviator,
                         VolumetricStrain };

struct LabColumn {
    LabQuantity quantity;
    double to_si = 1.0;  // multiply a value in the column's unit by this to get SI
};

// nullopt when the name is not part of the vocabulary.
std::optional<LabColumn> lab_column(const std::string& name);

// The whole text as a finite number ("1.5e3"); nullopt for anything else ("", "12 mm",
// "nan", "inf", beyond double). Every lab format reads its numbers through this, so they
// agree on what a reading is; each names the cell its own way when it is not one.
std::optional<double> finite_number(const std::string& s);

// Where a value came from, for error messages: a line/column or a JSON pointer.
struct LabCellOrigin {
    int line = 0, column = 0;
    std::string pointer;
};

// Appends one reading to the curve it belongs to (kind, stage, confining pressure),
// checking that every curve keeps the same set of measured columns.
class LabCurveCollector {
public:
    struct Cell {
        std::optional<double> value;  // already in SI
        LabCellOrigin origin;
    };
    // kind: "shear" or "creep"; empty optional cells are "not measured".
    void add(diagnose::CurveKind kind, int stage, double confining_pa, double stress_level,
             const std::vector<std::pair<LabQuantity, Cell>>& cells, const LabCellOrigin& row_origin);
    std::vector<diagnose::LabCurve> finish();

private:
    std::vector<diagnose::LabCurve> curves_;
    std::vector<std::vector<bool>> measured_;  // per curve: which quantities it carries
};

[[noreturn]] void throw_at(const LabCellOrigin& o, const std::string& msg);

}  // namespace triax::io
