#include "server/io/lab_format.hpp"
#include "server/io/bounded_json.hpp"
#include "server/io/lab_table.hpp"

#include <cmath>

namespace triax::io {

using diagnose::CurveKind;
using nlohmann::json;

std::optional<LabFormat> lab_format_from_name(std::string_view n) {
    if (n == "csv") return LabFormat::Csv;
    if (n == "gds") return LabFormat::Gds;
    if (n == "ags") return LabFormat::Ags;
    if (n == "json") return LabFormat::Json;
    return std::nullopt;
}

std::string lab_format_name(LabFormat f) {
    switch (f) {
        case LabFormat::Csv: return "csv";
        case LabFormat::Gds: return "gds";
        case LabFormat::Ags: return "ags";
        case LabFormat::Json: return "json";
    }
    return "csv";
}

LabFormat sniff_lab_format(std::string_view text) {
    const auto first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    if (first != std::string_view::npos && (text[first] == '{' || text[first] == '[')) return LabFormat::Json;
    if (text.find("\"GROUP\"") != std::string_view::npos) return LabFormat::Ags;
    if (text.find("Stage Number") != std::string_view::npos ||
        text.find("Time since start of stage") != std::string_view::npos)
        return LabFormat::Gds;
    return LabFormat::Csv;
}

diagnose::LabDataset parse_lab_dataset(std::string_view text, LabFormat format, std::vector<std::string>* notes) {
    switch (format) {
        case LabFormat::Csv: return parse_lab_csv(text, notes);
        case LabFormat::Gds: return parse_lab_gds(text);
        case LabFormat::Ags: return parse_lab_ags(text);
        case LabFormat::Json: {
            json doc;
            try {
                doc = parse_bounded_json(text);
            } catch (const JsonLimitError& e) {
                if (!e.syntax) throw LabParseError(e.what(), e.pointer.empty() ? std::string("/") : e.pointer);
                // Report the line/column of the byte nlohmann stopped at.
                int line = 1, col = 1;
                for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
                    if (text[i] == '\n') { ++line; col = 1; } else ++col;
                }
                throw LabParseError(std::string("invalid JSON: ") + e.what(), line, col);
            }
            return parse_lab_json(doc);
        }
    }
    return {};
}

namespace {

double number_at(const json& v, const std::string& ptr) {
    if (!v.is_number()) throw LabParseError("must be a number", ptr);
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw LabParseError("must be finite", ptr);
    return d;
}

double optional_number(const json& obj, const char* key, const std::string& ptr, double scale) {
    if (!obj.contains(key) || obj[key].is_null()) return 0.0;
    const double v = number_at(obj[key], ptr + "/" + key) * scale;
    if (!std::isfinite(v)) throw LabParseError("beyond the range of a reading", ptr + "/" + key);
    return v;
}

}  // namespace

diagnose::LabDataset parse_lab_json(const json& doc) {
    if (!doc.is_object()) throw LabParseError("a dataset must be a JSON object with 'curves'", std::string(""));
    diagnose::LabDataset d;
    if (doc.contains("name")) {
        if (!doc["name"].is_string()) throw LabParseError("must be a string", "/name");
        d.name = doc["name"].get<std::string>();
        if (d.name.size() > kMaxNameBytes)
            throw LabParseError("must be at most " + std::to_string(kMaxNameBytes) + " bytes", "/name");
    }
    LabCurveCollector collector;
    const json curves = doc.value("curves", json::array());
    if (!curves.is_array()) throw LabParseError("must be an array", "/curves");
    for (std::size_t i = 0; i < curves.size(); ++i) {
        const auto cptr = "/curves/" + std::to_string(i);
        const auto& c = curves[i];
        if (!c.is_object()) throw LabParseError("a curve must be an object", cptr);
        const auto kind_s = c.contains("kind") && c["kind"].is_string() ? c["kind"].get<std::string>() : std::string();
        if (kind_s != "shear" && kind_s != "creep") throw LabParseError("kind must be 'shear' or 'creep'", cptr + "/kind");
        const auto kind = kind_s == "creep" ? CurveKind::Creep : CurveKind::Shear;
        int stage = 0;
        if (kind == CurveKind::Creep) {
            if (!c.contains("stage") || !c["stage"].is_number_integer() || c["stage"].get<long long>() < 1 ||
                c["stage"].get<long long>() > kMaxStage)
                throw LabParseError("a creep curve needs an integer stage in [1, " + std::to_string(kMaxStage) + "]",
                                    cptr + "/stage");
            stage = c["stage"].get<int>();
        }
        if (!c.contains("confining_kPa")) throw LabParseError("required field 'confining_kPa' is missing", cptr + "/confining_kPa");
        const double confining = number_at(c["confining_kPa"], cptr + "/confining_kPa") * 1e3;
        if (confining <= 0) throw LabParseError("must be > 0", cptr + "/confining_kPa");
        const double s_level = optional_number(c, "stress_level", cptr, 1.0);
        if (!c.contains("columns") || !c["columns"].is_array()) throw LabParseError("must be an array of column names", cptr + "/columns");
        if (!c.contains("rows") || !c["rows"].is_array()) throw LabParseError("must be an array of rows", cptr + "/rows");
        std::vector<LabColumn> cols;
        for (std::size_t k = 0; k < c["columns"].size(); ++k) {
            const auto& n = c["columns"][k];
            const auto p = cptr + "/columns/" + std::to_string(k);
            auto col = n.is_string() ? lab_column(n.get<std::string>()) : std::nullopt;
            if (!col || col->quantity == LabQuantity::Kind || col->quantity == LabQuantity::Stage ||
                col->quantity == LabQuantity::Confining || col->quantity == LabQuantity::StressLevel)
                throw LabParseError("unknown series column " + n.dump() +
                                        " (time_min, axial_strain_pct, axial_deformation_mm, q_kPa, volumetric_strain_pct)",
                                    p);
            cols.push_back(*col);
        }
        if (c["rows"].empty()) throw LabParseError("a curve needs at least one row", cptr + "/rows");
        for (std::size_t r = 0; r < c["rows"].size(); ++r) {
            const auto rptr = cptr + "/rows/" + std::to_string(r);
            const auto& row = c["rows"][r];
            if (!row.is_array() || row.size() != cols.size())
                throw LabParseError("a row must be an array of " + std::to_string(cols.size()) + " values", rptr);
            std::vector<std::pair<LabQuantity, LabCurveCollector::Cell>> cells;
            for (std::size_t k = 0; k < cols.size(); ++k) {
                const auto p = rptr + "/" + std::to_string(k);
                LabCurveCollector::Cell cell;
                cell.origin.pointer = p;
                // Every declared column is measured in every row: a null would make the
                // collector read the column as "not measured" and drop it from the curve.
                if (row[k].is_null())
                    throw LabParseError("null reading: every column in 'columns' needs a number in every row "
                                        "(leave a column out of 'columns' when it was not measured)",
                                        p);
                cell.value = number_at(row[k], p) * cols[k].to_si;
                if (!std::isfinite(*cell.value)) throw LabParseError("beyond the range of a reading", p);
                cells.push_back({cols[k].quantity, cell});
            }
            LabCellOrigin o;
            o.pointer = rptr;
            collector.add(kind, stage, confining, s_level, cells, o);
        }
    }
    d.curves = collector.finish();
    const json summary = doc.value("summary", json::array());
    if (!summary.is_array()) throw LabParseError("must be an array", "/summary");
    for (std::size_t i = 0; i < summary.size(); ++i) {
        const auto p = "/summary/" + std::to_string(i);
        const auto& s = summary[i];
        if (!s.is_object()) throw LabParseError("a summary row must be an object", p);
        diagnose::LabSummaryRow row;
        if (s.contains("specimen") && !s["specimen"].is_string()) throw LabParseError("must be a string", p + "/specimen");
        row.specimen = s.value("specimen", std::string());
        if (row.specimen.size() > kMaxNameBytes)
            throw LabParseError("must be at most " + std::to_string(kMaxNameBytes) + " bytes", p + "/specimen");
        row.confining_pa = optional_number(s, "confining_kPa", p, 1e3);
        row.deviator_at_failure_pa = optional_number(s, "deviator_at_failure_kPa", p, 1e3);
        row.strain_at_failure = optional_number(s, "strain_at_failure_pct", p, 0.01);
        row.moisture_content = optional_number(s, "moisture_content_pct", p, 0.01);
        row.dry_density_kg_m3 = optional_number(s, "dry_density_kg_m3", p, 1.0);
        row.cohesion_pa = optional_number(s, "cohesion_kPa", p, 1e3);
        row.friction_angle_deg = optional_number(s, "friction_angle_deg", p, 1.0);
        d.summary.push_back(row);
    }
    if (d.curves.empty() && d.summary.empty()) throw LabParseError("the dataset has neither curves nor summary rows", "/curves");
    return d;
}

json lab_dataset_to_json(const diagnose::LabDataset& d) {
    json curves = json::array();
    for (const auto& c : d.curves) {
        json cols = json::array();
        std::vector<std::pair<const std::vector<double>*, double>> src;  // column, SI -> lab factor
        auto add = [&](const std::vector<double>& v, const char* name, double f) {
            if (!v.empty()) { cols.push_back(name); src.push_back({&v, f}); }
        };
        add(c.time_s, "time_min", 1.0 / 60.0);
        add(c.axial_strain, "axial_strain_pct", 100.0);
        add(c.axial_deformation_m, "axial_deformation_mm", 1e3);
        add(c.deviator_pa, "q_kPa", 1e-3);
        add(c.volumetric_strain, "volumetric_strain_pct", 100.0);
        json rows = json::array();
        for (std::size_t i = 0; i < c.size(); ++i) {
            json r = json::array();
            for (const auto& [v, f] : src) r.push_back((*v)[i] * f);
            rows.push_back(std::move(r));
        }
        json jc{{"kind", c.kind == CurveKind::Creep ? "creep" : "shear"},
                {"confining_kPa", c.confining_pa * 1e-3},
                {"columns", cols},
                {"rows", rows}};
        if (c.kind == CurveKind::Creep) jc["stage"] = c.stage;
        if (c.stress_level != 0.0) jc["stress_level"] = c.stress_level;
        curves.push_back(std::move(jc));
    }
    json summary = json::array();
    for (const auto& s : d.summary)
        summary.push_back({{"specimen", s.specimen},
                           {"confining_kPa", s.confining_pa * 1e-3},
                           {"deviator_at_failure_kPa", s.deviator_at_failure_pa * 1e-3},
                           {"strain_at_failure_pct", s.strain_at_failure * 100.0},
                           {"moisture_content_pct", s.moisture_content * 100.0},
                           {"dry_density_kg_m3", s.dry_density_kg_m3},
                           {"cohesion_kPa", s.cohesion_pa * 1e-3},
                           {"friction_angle_deg", s.friction_angle_deg}});
    return {{"name", d.name}, {"curves", curves}, {"summary", summary}};
}

json lab_curve_index(const diagnose::LabDataset& d) {
    json out = json::array();
    for (const auto& c : d.curves) {
        json e{{"kind", c.kind == CurveKind::Creep ? "creep" : "shear"},
               {"stage", c.kind == CurveKind::Creep ? json(c.stage) : json(nullptr)},
               {"confining_kPa", c.confining_pa * 1e-3},
               {"points", c.size()}};
        out.push_back(std::move(e));
    }
    return out;
}

}  // namespace triax::io
