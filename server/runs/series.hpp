#pragma once
// Result series of a run: the stored final series when the run is done, otherwise the
// rows rebuilt from its persisted events (partial results while running), then filtered
// by the query (stage, from/to range, uniform downsampling keeping first and last).
#include "server/runs/run_executor.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace triax::service {

struct SeriesQuery {
    std::optional<int> stage;
    std::optional<double> from, to;  // on the first non-"stage" column
    std::optional<std::size_t> max_points;
};

// rows: array of arrays in spec.columns order.
nlohmann::json filter_series(const SeriesSpec& spec, nlohmann::json rows, const SeriesQuery& q);
// Rows of a series from event data objects (missing fields become null).
nlohmann::json rows_from_events(const SeriesSpec& spec, const std::vector<nlohmann::json>& event_data);
// CSV text with the column names as header.
std::string series_csv(const std::vector<std::string>& columns, const nlohmann::json& rows);

}  // namespace triax::service
