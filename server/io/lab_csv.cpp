#include "server/io/lab_format.hpp"
#include "server/io/lab_table.hpp"

#include <cmath>
#include <map>

namespace triax::io {

using diagnose::CurveKind;

std::optional<LabColumn> lab_column(const std::string& raw) {
    std::string name;
    for (char c : raw) name += (c == ' ' ? '_' : c);
    static const std::map<std::string, LabColumn> table = {
        {"kind", {LabQuantity::Kind}},
        {"stage", {LabQuantity::Stage}},
        {"stress_level", {LabQuantity::StressLevel}},
        {"confining_kPa", {LabQuantity::Confining, 1e3}},
        {"confining_MPa", {LabQuantity::Confining, 1e6}},
        {"confining_Pa", {LabQuantity::Confining, 1.0}},
        {"sigma3_kPa", {LabQuantity::Confining, 1e3}},
        {"time_s", {LabQuantity::Time, 1.0}},
        {"time_min", {LabQuantity::Time, 60.0}},
        {"time_h", {LabQuantity::Time, 3600.0}},
        {"axial_strain_pct", {LabQuantity::AxialStrain, 0.01}},
        {"axial_strain_frac", {LabQuantity::AxialStrain, 1.0}},
        {"axial_deformation_mm", {LabQuantity::AxialDeformation, 1e-3}},
        {"axial_deformation_m", {LabQuantity::AxialDeformation, 1.0}},
        {"q_kPa", {LabQuantity::Deviator, 1e3}},
        {"q_MPa", {LabQuantity::Deviator, 1e6}},
        {"q_Pa", {LabQuantity::Deviator, 1.0}},
        {"deviator_kPa", {LabQuantity::Deviator, 1e3}},
        {"volumetric_strain_pct", {LabQuantity::VolumetricStrain, 0.01}},
        {"volumetric_strain_frac", {LabQuantity::VolumetricStrain, 1.0}},
    };
    auto it = table.find(name);
    if (it == table.end()) return std::nullopt;
    return it->second;
}

void throw_at(const LabCellOrigin& o, const std::string& msg) {
    if (!o.pointer.empty()) throw LabParseError(msg, o.pointer);
    throw LabParseError(msg, o.line, o.column);
}

namespace {
std::vector<double>* column_of(diagnose::LabCurve& c, LabQuantity q) {
    switch (q) {
        case LabQuantity::Time: return &c.time_s;
        case LabQuantity::AxialStrain: return &c.axial_strain;
        case LabQuantity::AxialDeformation: return &c.axial_deformation_m;
        case LabQuantity::Deviator: return &c.deviator_pa;
        case LabQuantity::VolumetricStrain: return &c.volumetric_strain;
        default: return nullptr;
    }
}
constexpr LabQuantity kSeries[] = {LabQuantity::Time, LabQuantity::AxialStrain, LabQuantity::AxialDeformation,
                                   LabQuantity::Deviator, LabQuantity::VolumetricStrain};
}  // namespace

void LabCurveCollector::add(CurveKind kind, int stage, double confining_pa, double stress_level,
                            const std::vector<std::pair<LabQuantity, Cell>>& cells, const LabCellOrigin& row_origin) {
    std::size_t idx = curves_.size();
    for (std::size_t i = 0; i < curves_.size(); ++i)
        if (curves_[i].kind == kind && curves_[i].stage == stage &&
            std::abs(curves_[i].confining_pa - confining_pa) <= 1e-9 * std::max(1.0, std::abs(confining_pa)))
            idx = i;
    if (idx == curves_.size()) {
        diagnose::LabCurve c;
        c.kind = kind;
        c.stage = stage;
        c.confining_pa = confining_pa;
        c.stress_level = stress_level;
        curves_.push_back(std::move(c));
        std::vector<bool> m(std::size(kSeries), false);
        for (const auto& [q, cell] : cells)
            for (std::size_t k = 0; k < std::size(kSeries); ++k)
                if (kSeries[k] == q && cell.value) m[k] = true;
        bool any = false;
        for (bool b : m) any = any || b;
        if (!any) throw_at(row_origin, "the reading has no measured value");
        measured_.push_back(std::move(m));
    }
    auto& curve = curves_[idx];
    for (const auto& [q, cell] : cells) {
        std::size_t k = 0;
        while (k < std::size(kSeries) && kSeries[k] != q) ++k;
        if (k == std::size(kSeries)) continue;
        if (cell.value.has_value() != measured_[idx][k])
            throw_at(cell.origin, cell.value ? "value given here but missing in the first reading of this curve"
                                             : "value missing here but given in the first reading of this curve");
        if (cell.value) column_of(curve, q)->push_back(*cell.value);
    }
}

std::vector<diagnose::LabCurve> LabCurveCollector::finish() { return std::move(curves_); }

std::optional<double> finite_number(const std::string& s) {
    try {
        std::size_t used = 0;
        const double v = std::stod(s, &used);
        if (used == s.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {  // not a number, or beyond double
    }
    return std::nullopt;
}

namespace {

double parse_number(const std::string& s, const LabCellOrigin& o, const std::string& column_name) {
    if (const auto v = finite_number(s)) return *v;
    throw_at(o, "column '" + column_name + "': '" + s + "' is not a finite number");
}

}  // namespace

diagnose::LabDataset parse_lab_csv(std::string_view text) {
    const auto records = read_csv_records(text);
    if (records.empty()) throw LabParseError("the file is empty", 1, 1);
    const auto& header = records.front();
    std::vector<LabColumn> cols;
    bool has_kind = false, has_confining = false;
    for (std::size_t c = 0; c < header.fields.size(); ++c) {
        auto col = lab_column(header.fields[c]);
        if (!col)
            throw LabParseError("unknown column '" + header.fields[c] +
                                    "' (expected names with units such as q_kPa, time_min, axial_strain_pct, "
                                    "axial_deformation_mm, volumetric_strain_pct, confining_kPa, kind, stage)",
                                header.line, header.columns[c]);
        for (const auto& prev : cols)
            if (prev.quantity == col->quantity && col->quantity != LabQuantity::Kind)
                throw LabParseError("column '" + header.fields[c] + "' repeats a quantity", header.line,
                                    header.columns[c]);
        has_kind = has_kind || col->quantity == LabQuantity::Kind;
        has_confining = has_confining || col->quantity == LabQuantity::Confining;
        cols.push_back(*col);
    }
    if (!has_confining) throw LabParseError("a confining pressure column (confining_kPa) is required", header.line, 1);

    LabCurveCollector collector;
    for (std::size_t r = 1; r < records.size(); ++r) {
        const auto& rec = records[r];
        if (rec.fields.size() != cols.size())
            throw LabParseError("expected " + std::to_string(cols.size()) + " fields, found " +
                                    std::to_string(rec.fields.size()),
                                rec.line, rec.columns.back());
        CurveKind kind = CurveKind::Shear;
        bool kind_given = false;
        int stage = 0;
        double confining = 0.0, stress_level = 0.0;
        std::vector<std::pair<LabQuantity, LabCurveCollector::Cell>> cells;
        for (std::size_t c = 0; c < cols.size(); ++c) {
            const LabCellOrigin o{rec.line, rec.columns[c], {}};
            const auto& f = rec.fields[c];
            switch (cols[c].quantity) {
                case LabQuantity::Kind:
                    if (f == "shear") kind = CurveKind::Shear;
                    else if (f == "creep") kind = CurveKind::Creep;
                    else throw_at(o, "kind must be 'shear' or 'creep', got '" + f + "'");
                    kind_given = true;
                    break;
                case LabQuantity::Stage: {
                    const double v = f.empty() ? 0.0 : parse_number(f, o, header.fields[c]);
                    if (v < 0 || v > 1000 || v != std::floor(v)) throw_at(o, "stage must be an integer in [0, 1000]");
                    stage = static_cast<int>(v);
                    break;
                }
                case LabQuantity::Confining:
                    if (f.empty()) throw_at(o, "the confining pressure is required on every reading");
                    confining = parse_number(f, o, header.fields[c]) * cols[c].to_si;
                    if (confining <= 0) throw_at(o, "the confining pressure must be > 0");
                    break;
                case LabQuantity::StressLevel:
                    if (!f.empty()) stress_level = parse_number(f, o, header.fields[c]);
                    break;
                default:
                    cells.push_back({cols[c].quantity,
                                     {f.empty() ? std::nullopt
                                                : std::optional<double>(parse_number(f, o, header.fields[c]) *
                                                                        cols[c].to_si),
                                      o}});
            }
        }
        if (!kind_given) kind = stage > 0 ? CurveKind::Creep : CurveKind::Shear;
        if (kind == CurveKind::Creep && stage < 1)
            throw_at({rec.line, rec.columns.front(), {}}, "a creep reading needs a stage number >= 1");
        if (kind == CurveKind::Shear) stage = 0;
        collector.add(kind, stage, confining, stress_level, cells, {rec.line, 1, {}});
    }
    diagnose::LabDataset d;
    d.curves = collector.finish();
    if (d.curves.empty()) throw LabParseError("the file has a header but no readings", header.line, 1);
    return d;
}

}  // namespace triax::io
