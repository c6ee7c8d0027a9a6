#include "server/io/lab_format.hpp"
#include "server/io/lab_table.hpp"

#include <cmath>
#include <map>

// AGS4 summary rows: TRET (one row per specimen) joined with TREG (per test set: cohesion,
// friction angle) on the key fields they share. Units come from each group's UNIT row.
namespace triax::io {

namespace {

struct Group {
    std::vector<std::string> headings, units;
    std::vector<const CsvRecord*> data;
    int heading_line = 0;
};

double to_si_factor(const std::string& unit, const CsvRecord& unit_rec, std::size_t c) {
    if (unit == "kPa" || unit.empty()) return unit == "kPa" ? 1e3 : 1.0;
    if (unit == "MPa") return 1e6;
    if (unit == "Pa") return 1.0;
    if (unit == "%") return 0.01;
    if (unit == "Mg/m3" || unit == "Mg/m³") return 1e3;
    if (unit == "kg/m3") return 1.0;
    if (unit == "deg" || unit == "°") return 1.0;
    if (unit == "mm" || unit == "-") return 1.0;
    throw LabParseError("unsupported unit '" + unit + "'", unit_rec.line, unit_rec.columns[c]);
}

}  // namespace

diagnose::LabDataset parse_lab_ags(std::string_view text) {
    const auto records = read_csv_records(text);
    std::map<std::string, Group> groups;
    std::map<std::string, const CsvRecord*> unit_rows;
    std::string current;
    for (const auto& r : records) {
        const auto& tag = r.fields[0];
        if (tag == "GROUP") {
            if (r.fields.size() < 2 || r.fields[1].empty()) throw LabParseError("GROUP without a name", r.line, 1);
            current = r.fields[1];
            // A group read twice would take the second HEADING for the first one's rows.
            if (groups.count(current)) throw LabParseError("group " + current + " appears twice", r.line, 1);
            groups[current];
        } else if (current.empty()) {
            throw LabParseError("'" + tag + "' row before any GROUP row", r.line, 1);
        } else if (tag == "HEADING") {
            if (!groups[current].headings.empty())
                throw LabParseError("group " + current + " has a second HEADING row", r.line, 1);
            groups[current].headings = r.fields;
            groups[current].heading_line = r.line;
        } else if (tag == "UNIT") {
            groups[current].units = r.fields;
            unit_rows[current] = &r;
        } else if (tag == "TYPE") {
        } else if (tag == "DATA") {
            auto& g = groups[current];
            if (g.headings.empty()) throw LabParseError("DATA row before the HEADING row of " + current, r.line, 1);
            if (r.fields.size() != g.headings.size())
                throw LabParseError("group " + current + " has " + std::to_string(g.headings.size()) +
                                        " headings but this row has " + std::to_string(r.fields.size()) + " fields",
                                    r.line, r.columns.back());
            g.data.push_back(&r);
        } else {
            throw LabParseError("unknown AGS row descriptor '" + tag + "' (GROUP, HEADING, UNIT, TYPE, DATA)", r.line, 1);
        }
    }
    if (!groups.count("TRET")) throw LabParseError("the file has no TRET group (triaxial test results)", 1, 1);
    const auto& tret = groups["TRET"];
    auto column = [](const Group& g, const std::string& name) -> std::optional<std::size_t> {
        for (std::size_t i = 0; i < g.headings.size(); ++i)
            if (g.headings[i] == name) return i;
        return std::nullopt;
    };
    auto value = [&](const Group& g, const std::string& group_name, const CsvRecord& r,
                     const std::string& name) -> double {
        auto c = column(g, name);
        if (!c || r.fields[*c].empty()) return 0.0;
        const auto& s = r.fields[*c];
        const auto parsed = finite_number(s);
        if (!parsed) throw LabParseError(name + ": '" + s + "' is not a finite number", r.line, r.columns[*c]);
        const double v = *parsed;
        const std::string unit = g.units.size() > *c ? g.units[*c] : std::string();
        const auto* ur = unit_rows.count(group_name) ? unit_rows.at(group_name) : &r;
        return v * to_si_factor(unit, *ur, *c);
    };
    static const char* keys[] = {"LOCA_ID", "SAMP_TOP", "SAMP_REF", "SAMP_TYPE", "SAMP_ID", "SPEC_REF", "SPEC_DPTH"};
    diagnose::LabDataset d;
    for (const auto* r : tret.data) {
        diagnose::LabSummaryRow row;
        std::string name;
        for (const char* k : {"LOCA_ID", "SAMP_ID", "SPEC_REF", "TRET_TESN"})
            if (auto c = column(tret, k); c && !r->fields[*c].empty()) name += (name.empty() ? "" : "/") + r->fields[*c];
        row.specimen = name;
        row.confining_pa = value(tret, "TRET", *r, "TRET_CELL");
        row.deviator_at_failure_pa = value(tret, "TRET", *r, "TRET_DEVF");
        row.strain_at_failure = value(tret, "TRET", *r, "TRET_STRN");
        row.moisture_content = value(tret, "TRET", *r, "TRET_IMC");
        row.dry_density_kg_m3 = value(tret, "TRET", *r, "TRET_DDEN");
        // The same physical ranges as the CSV and JSON readers (a negative cell pressure is
        // refused there too).
        auto require_at = [&](bool ok, const char* name, const std::string& why) {
            if (ok) return;
            const auto c = column(tret, name);
            throw LabParseError(std::string(name) + ": " + why, r->line, c ? r->columns[*c] : 1);
        };
        require_at(row.confining_pa >= 0.0, "TRET_CELL", "the cell pressure must be >= 0");
        require_at(row.strain_at_failure >= 0.0 && row.strain_at_failure <= 1.0, "TRET_STRN",
                   "the strain at failure must be in [0, 100] %");
        require_at(row.moisture_content >= 0.0 && row.moisture_content <= 5.0, "TRET_IMC",
                   "the moisture content must be in [0, 500] %");
        require_at(row.dry_density_kg_m3 >= 0.0 && row.dry_density_kg_m3 <= 5000.0, "TRET_DDEN",
                   "the dry density must be in [0, 5] Mg/m3");
        if (groups.count("TREG")) {
            const auto& treg = groups["TREG"];
            for (const auto* g : treg.data) {
                bool match = true;
                for (const char* k : keys) {
                    auto a = column(tret, k), b = column(treg, k);
                    if (a && b && r->fields[*a] != g->fields[*b]) match = false;
                }
                if (match) {
                    row.cohesion_pa = value(treg, "TREG", *g, "TREG_COH");
                    row.friction_angle_deg = value(treg, "TREG", *g, "TREG_PHI");
                    break;
                }
            }
        }
        d.summary.push_back(row);
    }
    if (d.summary.empty()) throw LabParseError("the TRET group has no DATA rows", tret.heading_line, 1);
    return d;
}

}  // namespace triax::io
