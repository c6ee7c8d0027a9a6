#include "server/io/lab_format.hpp"
#include "server/io/lab_stage_kind.hpp"
#include "server/io/lab_table.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <string_view>

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
        // Common spellings of lab exports.
        {"vol_strain_pct", {LabQuantity::VolumetricStrain, 0.01}},
        {"vol_strain_frac", {LabQuantity::VolumetricStrain, 1.0}},
        {"volume_strain_pct", {LabQuantity::VolumetricStrain, 0.01}},
        {"deviator_MPa", {LabQuantity::Deviator, 1e6}},
        {"deviator_stress_kPa", {LabQuantity::Deviator, 1e3}},
        {"cell_pressure_kPa", {LabQuantity::Confining, 1e3}},
        {"sigma3_MPa", {LabQuantity::Confining, 1e6}},
        {"axial_displacement_mm", {LabQuantity::AxialDeformation, 1e-3}},
        {"time_hr", {LabQuantity::Time, 3600.0}},
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

std::optional<double> finite_number(const std::string& raw) {
    // Decimal notation only: std::stod would also read "0x10" (16), "inf" and "nan".
    std::size_t b = raw.find_first_not_of(" \t"), e = raw.find_last_not_of(" \t");
    if (b == std::string::npos) return std::nullopt;
    std::string_view s(raw.data() + b, e - b + 1);
    if (s.front() == '+') s.remove_prefix(1);
    if (s.empty() || s.front() == '+') return std::nullopt;
    for (char c : s)
        if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == 'e' || c == 'E' || c == '+'))
            return std::nullopt;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

namespace {

double parse_number(const std::string& s, const LabCellOrigin& o, const std::string& column_name) {
    if (const auto v = finite_number(s)) return *v;
    throw_at(o, "column '" + column_name + "': '" + s + "' is not a finite number");
}

}  // namespace

namespace {

// The field separator of the header line: ',' unless the line has none and has ';' or a
// tab (spreadsheet exports in locales with a decimal comma use ';').
char detect_separator(std::string_view text) {
    const auto nl = text.find('\n');
    const auto first = text.substr(0, nl);
    if (first.find(',') != std::string_view::npos) return ',';
    if (first.find(';') != std::string_view::npos) return ';';
    if (first.find('\t') != std::string_view::npos) return '\t';
    return ',';
}

struct CsvRow {
    int line = 0;
    bool kind_given = false;
    CurveKind kind = CurveKind::Shear;
    int stage = 0;
    double confining = 0.0, stress_level = 0.0;
    std::vector<std::pair<LabQuantity, LabCurveCollector::Cell>> cells;
    bool loading_ramp = false;  // the ramp before a creep stage's hold: not part of its curve
};

std::optional<double> value_of(const CsvRow& row, LabQuantity q) {
    for (const auto& [quantity, cell] : row.cells)
        if (quantity == q) return cell.value;
    return std::nullopt;
}

}  // namespace

diagnose::LabDataset parse_lab_csv(std::string_view text, std::vector<std::string>* notes) {
    const char sep = detect_separator(text);
    const auto records = read_csv_records(text, sep);
    if (records.empty()) throw LabParseError("the file is empty", 1, 1);
    const auto& header = records.front();
    if (notes && sep != ',')
        notes->push_back(std::string("fields separated by '") + (sep == '\t' ? "\\t" : ";") +
                         "' (detected from the header line)" + (sep == ';' ? "; a decimal comma is read as a point" : ""));
    std::vector<LabColumn> cols;
    bool has_kind = false, has_confining = false, has_stage = false, has_q = false;
    for (std::size_t c = 0; c < header.fields.size(); ++c) {
        auto col = lab_column(header.fields[c]);
        if (!col) {
            std::string hint;
            for (char d : {';', '\t', '|'})
                if (header.fields[c].find(d) != std::string::npos)
                    hint = std::string(" - the header holds '") + (d == '\t' ? "\\t" : std::string(1, d)) +
                           "': are the fields separated by it? Use ',' (or ';' or tab throughout the file)";
            throw LabParseError("unknown column '" + header.fields[c] +
                                    "' (expected names with units such as q_kPa, time_min, axial_strain_pct, "
                                    "axial_deformation_mm, volumetric_strain_pct, confining_kPa, kind, stage)" + hint,
                                header.line, header.columns[c]);
        }
        for (const auto& prev : cols)
            if (prev.quantity == col->quantity && col->quantity != LabQuantity::Kind)
                throw LabParseError("column '" + header.fields[c] + "' repeats a quantity", header.line,
                                    header.columns[c]);
        has_kind = has_kind || col->quantity == LabQuantity::Kind;
        has_confining = has_confining || col->quantity == LabQuantity::Confining;
        has_stage = has_stage || col->quantity == LabQuantity::Stage;
        has_q = has_q || col->quantity == LabQuantity::Deviator;
        cols.push_back(*col);
    }
    if (!has_confining) throw LabParseError("a confining pressure column (confining_kPa) is required", header.line, 1);

    // With ';' between fields the numbers may use a decimal comma.
    auto number = [&](const std::string& f, const LabCellOrigin& o, const std::string& name) {
        if (sep == ';' && f.find(',') != std::string::npos && f.find('.') == std::string::npos) {
            std::string dotted = f;
            std::replace(dotted.begin(), dotted.end(), ',', '.');
            return parse_number(dotted, o, name);
        }
        return parse_number(f, o, name);
    };

    std::vector<CsvRow> rows;
    for (std::size_t r = 1; r < records.size(); ++r) {
        const auto& rec = records[r];
        if (rec.fields.size() != cols.size())
            throw LabParseError("expected " + std::to_string(cols.size()) + " fields, found " +
                                    std::to_string(rec.fields.size()),
                                rec.line, rec.columns.back());
        CsvRow row;
        row.line = rec.line;
        for (std::size_t c = 0; c < cols.size(); ++c) {
            const LabCellOrigin o{rec.line, rec.columns[c], {}};
            const auto& f = rec.fields[c];
            switch (cols[c].quantity) {
                case LabQuantity::Kind:
                    if (f == "shear") row.kind = CurveKind::Shear;
                    else if (f == "creep") row.kind = CurveKind::Creep;
                    else throw_at(o, "kind must be 'shear' or 'creep', got '" + f + "'");
                    row.kind_given = true;
                    break;
                case LabQuantity::Stage: {
                    const double v = f.empty() ? 0.0 : number(f, o, header.fields[c]);
                    if (v < 0 || v > static_cast<double>(kMaxStage) || v != std::floor(v))
                        throw_at(o, "stage must be an integer in [0, " + std::to_string(kMaxStage) + "]");
                    row.stage = static_cast<int>(v);
                    break;
                }
                case LabQuantity::Confining:
                    if (f.empty()) throw_at(o, "the confining pressure is required on every reading");
                    row.confining = number(f, o, header.fields[c]) * cols[c].to_si;
                    if (!(row.confining > 0) || !std::isfinite(row.confining))
                        throw_at(o, "the confining pressure must be > 0");
                    break;
                case LabQuantity::StressLevel:
                    if (!f.empty()) row.stress_level = number(f, o, header.fields[c]);
                    break;
                default:
                    row.cells.push_back({cols[c].quantity,
                                         {f.empty() ? std::nullopt
                                                    : std::optional<double>(number(f, o, header.fields[c]) *
                                                                            cols[c].to_si),
                                          o}});
            }
        }
        rows.push_back(std::move(row));
    }

    // No kind column: stage 0 is shear; a numbered stage's kind is read from its readings
    // (lab_stage_kind.hpp), since lab exports number every stage, shear included. A creep
    // stage that begins with its loading ramp starts where q reaches its held value: its
    // clock starts there, and its deformation counts from the ramp's first reading (the
    // level before loading), so the ramp's deformation is the stage's instantaneous part.
    if (!has_kind && has_stage) {
        std::map<std::pair<int, double>, std::vector<std::size_t>> groups;
        for (std::size_t i = 0; i < rows.size(); ++i)
            if (rows[i].stage > 0) groups[{rows[i].stage, rows[i].confining}].push_back(i);
        for (const auto& [key, members] : groups) {
            const std::string which = "stage " + std::to_string(key.first) + " at " +
                                      std::to_string(static_cast<long long>(std::lround(key.second * 1e-3))) + " kPa";
            const LabCellOrigin first{rows[members.front()].line, 1, {}};
            if (!has_q)
                throw_at(first, which + ": without a kind column the kind is read from q, and there is no q column; "
                                        "add a kind column (shear or creep)");
            // The deformation the rules read: axial strain, else axial deformation.
            const LabQuantity deformation =
                value_of(rows[members.front()], LabQuantity::AxialStrain) ? LabQuantity::AxialStrain
                                                                          : LabQuantity::AxialDeformation;
            StageReadings readings;
            bool timed = true, deformed = true;
            for (auto i : members) {
                const auto q = value_of(rows[i], LabQuantity::Deviator);
                if (!q)
                    throw_at({rows[i].line, 1, {}}, which + ": q is missing on this reading; without a kind column "
                                                            "the kind is read from q (add a kind column)");
                readings.q.push_back(*q * 1e-3);
                readings.line.push_back(rows[i].line);
                const auto t = value_of(rows[i], LabQuantity::Time);
                const auto e = value_of(rows[i], deformation);
                timed = timed && t.has_value();
                deformed = deformed && e.has_value();
                readings.time.push_back(t.value_or(0.0));
                readings.deformation.push_back(e.value_or(0.0));
            }
            if (!timed) readings.time.clear();
            if (!deformed) readings.deformation.clear();
            const StageKind shape = classify_stage(readings);
            if (shape.verdict == StageKind::Verdict::Ambiguous)
                throw_at(first, which + ": cannot tell shear from creep: " + shape.reason + "; add a kind column (shear or creep)");
            const CurveKind kind = shape.verdict == StageKind::Verdict::Creep ? CurveKind::Creep : CurveKind::Shear;
            for (auto i : members) rows[i].kind = kind;
            std::string note = which + ": read as " + (kind == CurveKind::Creep ? "creep" : "shear") + " (" + shape.reason +
                               ") - no kind column";
            if (kind == CurveKind::Creep && shape.hold_begin > 0) {
                const CsvRow& before = rows[members.front()];
                const CsvRow& held = rows[members[shape.hold_begin]];
                const auto t0 = value_of(held, LabQuantity::Time);
                for (std::size_t k = 0; k < members.size(); ++k) {
                    CsvRow& row = rows[members[k]];
                    if (k < shape.hold_begin) {
                        row.loading_ramp = true;
                        continue;
                    }
                    for (auto& [quantity, cell] : row.cells) {
                        if (!cell.value) continue;
                        if (quantity == LabQuantity::Time && t0) *cell.value -= *t0;
                        if (quantity == LabQuantity::AxialStrain || quantity == LabQuantity::AxialDeformation ||
                            quantity == LabQuantity::VolumetricStrain)
                            if (const auto origin = value_of(before, quantity)) *cell.value -= *origin;
                        if (!std::isfinite(*cell.value))
                            throw_at(cell.origin, "beyond the range of a reading once counted from the stage's origin");
                    }
                }
                note += "; its loading ramp (lines " + std::to_string(before.line) + "-" +
                        std::to_string(rows[members[shape.hold_begin - 1]].line) + ") is left out: time from line " +
                        std::to_string(held.line) + ", deformation from line " + std::to_string(before.line) +
                        " (the ramp's deformation is the stage's instantaneous part)";
            }
            if (notes) notes->push_back(note);
        }
        // Numbered shear stages are ordinary shear curves.
        for (auto& row : rows)
            if (row.stage > 0) row.kind_given = true;
    }

    LabCurveCollector collector;
    for (auto& row : rows) {
        if (row.loading_ramp) continue;
        CurveKind kind = row.kind;
        int stage = row.stage;
        if (!row.kind_given) kind = CurveKind::Shear;
        if (kind == CurveKind::Creep && stage < 1)
            throw_at({row.line, 1, {}}, "a creep reading needs a stage number >= 1");
        if (kind == CurveKind::Shear) stage = 0;
        collector.add(kind, stage, row.confining, row.stress_level, row.cells, {row.line, 1, {}});
    }
    diagnose::LabDataset d;
    d.curves = collector.finish();
    if (d.curves.empty()) throw LabParseError("the file has a header but no readings", header.line, 1);
    return d;
}

}  // namespace triax::io
