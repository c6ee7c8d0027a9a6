#include "server/io/lab_format.hpp"
#include "server/io/lab_stage_kind.hpp"
#include "server/io/lab_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

// GDS-Lab-style export: one row per reading, stages numbered by the logger. Conventions
// taken here (also in docs/service.md):
//  - stages whose deviator stays below 1 kPa (saturation, consolidation) are skipped;
//  - a stage's kind is read from its readings as for a CSV stage without a kind column
//    (lab_stage_kind.hpp: a creep stage holds q, possibly after its loading ramp; a shear
//    stage's strain grows while q rises, peaks, softens or plateaus); a stage those rules
//    cannot place keeps the older rule (creep when >= 80 % of its readings lie within 5 %
//    of its median deviator, else shear) rather than refusing an export that has no kind
//    column to add;
//  - creep stages are renumbered 1..n in order; their axial deformation is measured from
//    the last reading before the stage (so the instantaneous deformation of the load step
//    is kept), their time is "Time since start of stage"; a loading ramp at the start of
//    the stage is left out and the stage's time starts at its first held reading;
//  - shear strains are rebased to the first reading of the shear stage;
//  - "Volume Change (mm3)" positive = water out of the specimen = contraction; volumetric
//    strain needs the initial height and diameter from the preamble.
//  - confining pressure = Eff. Radial Stress if present, else Radial Pressure - Back Pressure;
//  - without "Time since start of stage (s)", stage time is rebased from "Time since start
//    of test (s)" at the stage's first reading.
namespace triax::io {

using diagnose::CurveKind;

namespace {

std::string normalise(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (std::isspace(static_cast<unsigned char>(c))) {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

double number_in(const CsvRecord& r, std::size_t c, const std::string& name) {
    const auto& s = r.fields[c];
    if (const auto v = finite_number(s)) return *v;
    throw LabParseError("column '" + name + "': '" + s + "' is not a finite number", r.line, r.columns[c]);
}

struct Reading {
    const CsvRecord* rec;
    int stage;
    double t_s, disp_mm, strain, q_kpa, dvol_mm3, confining_kpa;
    bool has_disp, has_strain, has_dvol;
};

}  // namespace

diagnose::LabDataset parse_lab_gds(std::string_view text) {
    const char sep = [&] {
        const auto nl = text.find('\n');
        const auto first = text.substr(0, nl);
        return first.find('\t') != std::string_view::npos && first.find(',') == std::string_view::npos ? '\t' : ',';
    }();
    auto records = read_csv_records(text, sep);
    std::size_t h = 0;
    double height_mm = 0.0, diameter_mm = 0.0;
    for (; h < records.size(); ++h) {
        const auto& f = records[h].fields;
        bool is_header = false;
        for (const auto& x : f) is_header = is_header || normalise(x) == "stage number";
        if (is_header) break;
        if (f.size() >= 2) {  // preamble "key, value"
            const auto key = normalise(f[0]);
            const bool height = key.rfind("initial height", 0) == 0 || key == "height (mm)";
            const bool diameter = key.rfind("initial diameter", 0) == 0 || key == "diameter (mm)";
            if (height || diameter) {
                // The whole cell: "nan" or "80 mm" used to pass (std::stod alone).
                const auto v = finite_number(f[1]);
                if (!v) throw LabParseError("'" + f[0] + "' must be a finite number", records[h].line, records[h].columns[1]);
                (height ? height_mm : diameter_mm) = *v;
            }
        }
    }
    if (h == records.size()) throw LabParseError("no header row with a 'Stage Number' column was found", 1, 1);
    if (height_mm < 0 || height_mm > 1.0e4 || diameter_mm < 0 || diameter_mm > 1.0e4)
        throw LabParseError("the specimen height and diameter must be in (0, 10000] mm", 1, 1);
    const auto& header = records[h];
    std::map<std::string, std::size_t> idx;
    for (std::size_t c = 0; c < header.fields.size(); ++c) idx[normalise(header.fields[c])] = c;
    auto find = [&](std::initializer_list<const char*> names) -> std::optional<std::size_t> {
        for (const char* n : names)
            if (auto it = idx.find(n); it != idx.end()) return it->second;
        return std::nullopt;
    };
    const auto c_stage = find({"stage number"});
    const auto c_time = find({"time since start of stage (s)"});
    const auto c_test_time = find({"time since start of test (s)"});
    const auto c_disp = find({"axial displacement (mm)"});
    const auto c_strain = find({"axial strain (%)"});
    const auto c_q = find({"deviator stress (kpa)"});
    const auto c_dvol = find({"volume change (mm3)", "volume change (mm³)"});
    const auto c_eff_radial = find({"eff. radial stress (kpa)", "eff radial stress (kpa)"});
    const auto c_radial = find({"radial pressure (kpa)"});
    const auto c_back = find({"back pressure (kpa)"});
    auto missing = [&](const char* what) {
        return LabParseError(std::string("required column '") + what + "' is missing", header.line, 1);
    };
    if (!c_time && !c_test_time) throw missing("Time since start of stage (s)");
    // Without the stage clock, stage time = test time - test time of the stage's first reading.
    const bool rebase_time = !c_time;
    if (!c_q) throw missing("Deviator Stress (kPa)");
    if (!c_disp && !c_strain) throw missing("Axial Displacement (mm)");
    if (!c_eff_radial && !c_radial) throw missing("Radial Pressure (kPa)");
    if (!c_strain && height_mm <= 0)
        throw LabParseError("without an 'Axial Strain (%)' column the preamble must give 'Initial Height (mm)'",
                            header.line, 1);

    std::vector<Reading> rows;
    for (std::size_t r = h + 1; r < records.size(); ++r) {
        const auto& rec = records[r];
        if (rec.fields.size() < header.fields.size())
            throw LabParseError("expected " + std::to_string(header.fields.size()) + " fields, found " +
                                    std::to_string(rec.fields.size()),
                                rec.line, rec.columns.back());
        auto num = [&](std::optional<std::size_t> c) { return number_in(rec, *c, header.fields[*c]); };
        // Physical ranges, each refused at its cell (a logger writes none of these).
        auto in_range = [&](std::optional<std::size_t> c, double lo, double hi, const std::string& why) {
            const double v = num(c);
            if (!(v >= lo && v <= hi))
                throw LabParseError("column '" + header.fields[*c] + "': " + why, rec.line, rec.columns[*c]);
            return v;
        };
        Reading x{};
        x.rec = &rec;
        const double stage = in_range(c_stage, 0.0, static_cast<double>(kMaxStage),
                                      "the stage number must be an integer in [0, " + std::to_string(kMaxStage) + "]");
        if (stage != std::floor(stage))
            throw LabParseError("column '" + header.fields[*c_stage] + "': the stage number must be an integer", rec.line,
                                rec.columns[*c_stage]);
        x.stage = static_cast<int>(stage);
        const auto c_t = c_time ? c_time : c_test_time;
        x.t_s = in_range(c_t, 0.0, 1.0e9, "the time must be in [0, 1e9] s");
        x.q_kpa = in_range(c_q, -1.0e6, 1.0e6, "the deviator stress must be within +-1e6 kPa");
        x.has_disp = c_disp.has_value();
        x.has_strain = c_strain.has_value() || height_mm > 0;
        if (c_disp) x.disp_mm = in_range(c_disp, -1.0e4, 1.0e4, "the axial displacement must be within +-10 m");
        x.strain = c_strain ? in_range(c_strain, -100.0, 100.0, "the axial strain must be within +-100 %") / 100.0
                            : x.disp_mm / height_mm;
        // Within a stage the clock runs forward; a new stage may restart it.
        if (!rows.empty() && rows.back().stage == x.stage && x.t_s < rows.back().t_s)
            throw LabParseError("column '" + header.fields[*c_t] + "': the time runs backwards within stage " +
                                    std::to_string(x.stage) + " (" + std::to_string(rows.back().t_s) + " s on line " +
                                    std::to_string(rows.back().rec->line) + ")",
                                rec.line, rec.columns[*c_t]);
        x.has_dvol = c_dvol && height_mm > 0 && diameter_mm > 0;
        if (x.has_dvol) x.dvol_mm3 = num(c_dvol);
        x.confining_kpa = c_eff_radial ? in_range(c_eff_radial, -1.0e6, 1.0e6, "must be within +-1e6 kPa")
                                       : in_range(c_radial, -1.0e6, 1.0e6, "must be within +-1e6 kPa") -
                                             (c_back ? in_range(c_back, -1.0e6, 1.0e6, "must be within +-1e6 kPa") : 0.0);
        rows.push_back(x);
    }
    if (rows.empty()) throw LabParseError("the header is not followed by readings", header.line, 1);

    const double v0_mm3 = M_PI * 0.25 * diameter_mm * diameter_mm * height_mm;
    LabCurveCollector collector;
    int creep_count = 0;
    for (std::size_t begin = 0; begin < rows.size();) {
        std::size_t end = begin;
        while (end < rows.size() && rows[end].stage == rows[begin].stage) ++end;
        std::vector<double> q;
        for (std::size_t i = begin; i < end; ++i) q.push_back(rows[i].q_kpa);
        std::vector<double> sorted = q;
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        const double median = sorted[sorted.size() / 2];
        const double qmax = *std::max_element(q.begin(), q.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
        if (std::abs(qmax) >= 1.0) {
            StageReadings readings;
            readings.q = q;
            for (std::size_t i = begin; i < end; ++i) {
                readings.time.push_back(rows[i].t_s);
                readings.deformation.push_back(rows[i].strain);
                readings.line.push_back(rows[i].rec->line);
            }
            const StageKind shape = classify_stage(readings);
            bool creep = shape.verdict == StageKind::Verdict::Creep;
            if (shape.verdict == StageKind::Verdict::Ambiguous) {
                std::size_t near = 0;
                for (double v : q) near += std::abs(v - median) <= 0.05 * std::abs(median);
                creep = median > 1.0 && near >= 0.8 * static_cast<double>(q.size()) && q.size() >= 2;
            }
            // A creep stage's loading ramp is not part of its curve; its clock starts where q is held.
            const std::size_t held = creep ? begin + shape.hold_begin : begin;
            const Reading& first = rows[begin];
            const Reading& before = begin > 0 ? rows[begin - 1] : first;
            double confining = 0.0;
            for (std::size_t i = begin; i < end; ++i) confining += rows[i].confining_kpa;
            confining /= static_cast<double>(end - begin);
            if (confining <= 0)
                throw LabParseError("stage " + std::to_string(first.stage) + " has a non-positive confining pressure",
                                    first.rec->line, 1);
            const int stage = creep ? ++creep_count : 0;
            for (std::size_t i = held; i < end; ++i) {
                const auto& x = rows[i];
                const LabCellOrigin o{x.rec->line, 1, {}};
                std::vector<std::pair<LabQuantity, LabCurveCollector::Cell>> cells;
                const double clock0 = held > begin ? rows[held].t_s : rebase_time ? first.t_s : 0.0;
                cells.push_back({LabQuantity::Time, {x.t_s - clock0, o}});
                cells.push_back({LabQuantity::Deviator, {x.q_kpa * 1e3, o}});
                if (creep) {
                    if (x.has_disp) cells.push_back({LabQuantity::AxialDeformation, {(x.disp_mm - before.disp_mm) * 1e-3, o}});
                    if (x.has_strain) cells.push_back({LabQuantity::AxialStrain, {x.strain - before.strain, o}});
                } else {
                    cells.push_back({LabQuantity::AxialStrain, {x.strain - first.strain, o}});
                    if (x.has_dvol)
                        cells.push_back({LabQuantity::VolumetricStrain, {(x.dvol_mm3 - first.dvol_mm3) / v0_mm3, o}});
                }
                collector.add(creep ? CurveKind::Creep : CurveKind::Shear, stage, confining * 1e3, 0.0, cells, o);
            }
        }
        begin = end;
    }
    diagnose::LabDataset d;
    d.curves = collector.finish();
    if (d.curves.empty())
        throw LabParseError("no shear or creep stage found (every stage has a deviator stress below 1 kPa)", header.line, 1);
    return d;
}

}  // namespace triax::io
