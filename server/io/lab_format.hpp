#pragma once
// Parsers of uploaded laboratory readings into the canonical LabDataset (SI inside,
// soil-mechanics signs). Formats:
//   csv  plain CSV whose header names carry units: kind, stage, confining_kPa, stress_level,
//        time_min|time_s|time_h, axial_strain_pct, axial_deformation_mm, q_kPa,
//        volumetric_strain_pct (kPa|MPa|Pa, pct|frac, mm|m accepted as suffixes)
//   gds  GDS-Lab-style export: optional "key, value" preamble, then a header row with
//        the usual column names ("Stage Number", "Time since start of stage (s)", ...)
//   ags  AGS4 TREG/TRET groups: summary rows only (no curves)
//   json {"name", "curves":[{"kind","stage","confining_kPa","columns":[..],"rows":[[..]]}],
//         "summary":[{...}]} with the same column names as csv
// Every error names the 1-based line and column (csv/gds/ags) or the JSON pointer (json).
#include "engine/diagnose/lab_data.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace triax::io {

struct LabParseError : std::runtime_error {
    int line = 0, column = 0;     // 1-based; 0 when not applicable
    std::string field;            // JSON pointer for json uploads
    LabParseError(const std::string& msg, int line, int column)
        : std::runtime_error("line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + msg),
          line(line), column(column) {}
    LabParseError(const std::string& msg, std::string pointer)
        : std::runtime_error(pointer + ": " + msg), field(std::move(pointer)) {}
};

enum class LabFormat { Csv, Gds, Ags, Json };

// Limits shared by every format: names (dataset, specimen) and stage numbers.
inline constexpr std::size_t kMaxNameBytes = 200;
inline constexpr long long kMaxStage = 1000;

std::optional<LabFormat> lab_format_from_name(std::string_view name);  // "csv","gds","ags","json"
std::string lab_format_name(LabFormat f);
// Guesses the format from the content (JSON brace, AGS "GROUP" line, GDS column names).
LabFormat sniff_lab_format(std::string_view text);

// `notes` (optional) receives what the reader inferred (separator, the kind of a stage
// read from its q readings) so the answer can say so.
diagnose::LabDataset parse_lab_csv(std::string_view text, std::vector<std::string>* notes = nullptr);
diagnose::LabDataset parse_lab_gds(std::string_view text);
diagnose::LabDataset parse_lab_ags(std::string_view text);
diagnose::LabDataset parse_lab_json(const nlohmann::json& doc);
diagnose::LabDataset parse_lab_dataset(std::string_view text, LabFormat format,
                                       std::vector<std::string>* notes = nullptr);

// The dataset in lab units, in the JSON upload form (parse_lab_json reads it back).
nlohmann::json lab_dataset_to_json(const diagnose::LabDataset& d);
// Short description of each curve for listings: kind, stage, confining_kPa, points.
nlohmann::json lab_curve_index(const diagnose::LabDataset& d);

// Shared by the text parsers: one CSV record split into fields, quotes removed.
struct CsvRecord {
    int line = 0;
    std::vector<std::string> fields;
    std::vector<int> columns;  // 1-based character column where each field starts
};
std::vector<CsvRecord> read_csv_records(std::string_view text, char separator = ',');

}  // namespace triax::io
