#include "server/io/result_csv.hpp"

#include <sstream>

#include "server/io/result_json.hpp"

namespace triax::io {

std::string series_json_to_csv(const nlohmann::json& series) {
    std::ostringstream out;
    out.precision(10);
    const auto& cols = series.at("columns");
    for (std::size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i].get<std::string>();
    out << "\n";
    for (const auto& row : series.at("rows")) {
        for (std::size_t i = 0; i < row.size(); ++i) {
            if (i) out << ",";
            if (row[i].is_number_integer()) out << row[i].get<long long>();
            else if (row[i].is_number()) out << row[i].get<double>();
            else if (!row[i].is_null()) out << row[i].dump();
        }
        out << "\n";
    }
    return out.str();
}

std::string result_series_to_csv(const protocol::TestResult& r, const std::string& series) {
    return series_json_to_csv(result_series_to_json(r, series));
}

}  // namespace triax::io
