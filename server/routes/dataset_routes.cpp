// POST /datasets (csv | gds | ags | json upload), GET /datasets, GET /datasets/{id},
// DELETE /datasets/{id}. The stored form is the canonical dataset in lab units
// (lab_dataset_to_json), so every format reads back the same way.
#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/http/stored_document.hpp"
#include "server/io/lab_format.hpp"
#include "server/service.hpp"

#include <algorithm>
#include <optional>

namespace triax::service {

using nlohmann::json;

namespace {

// The stored part of a listing entry (datasets.header_json): curve index and summary rows.
json header_columns(const diagnose::LabDataset& d) {
    return {{"curves", io::lab_curve_index(d)}, {"summary", io::lab_dataset_to_json(d)["summary"]}};
}

json dataset_header(const DatasetRow& row, const json& header) {
    return {{"id", row.id},
            {"name", row.name},
            {"format", row.format},
            {"created_at", row.created_at},
            {"curves", header.value("curves", json::array())},
            {"summary", header.value("summary", json::array())}};
}

}  // namespace

diagnose::LabDataset load_dataset(Service& s, std::int64_t id, std::string* name) {
    // The text is read under the database lock, parsed outside it.
    return io::parse_lab_json(json::parse(s.datasets.dataset_text(id, name)));
}

int backfill_dataset_headers(Service& s) {
    const auto ids = s.datasets.ids_without_header();
    for (const auto id : ids) s.datasets.set_header(id, header_columns(load_dataset(s, id, nullptr)));
    return static_cast<int>(ids.size());
}

void register_dataset_routes(Service& s) {
    s.route("POST", "/datasets", [&s](const httplib::Request& req, httplib::Response& res) {
        if (req.body.empty()) throw bad_request("the request body is empty; upload the file as the body");
        // Stored datasets are served as JSON (UTF-8 only): a bad byte is refused here with
        // its position, instead of being stored and breaking every later listing.
        if (const auto at = invalid_utf8_at(req.body); at != std::string::npos) {
            const auto line_start = req.body.rfind('\n', at == 0 ? 0 : at - 1);
            const auto head = std::string_view(req.body).substr(0, at);
            const int line = 1 + static_cast<int>(std::count(head.begin(), head.end(), '\n'));
            const int column = static_cast<int>(at - (line_start == std::string::npos || at == 0 ? 0 : line_start + 1)) + 1;
            throw unprocessable("the file is not UTF-8 text: invalid byte at line " + std::to_string(line) + ", column " +
                                std::to_string(column) + " (save it as UTF-8)")
                .at(line, column);
        }
        io::LabFormat format;
        if (req.has_param("format")) {
            auto f = io::lab_format_from_name(req.get_param_value("format"));
            if (!f) throw bad_request("format must be one of csv, gds, ags, json; got '" + req.get_param_value("format") + "'");
            format = *f;
        } else {
            format = io::sniff_lab_format(req.body);
        }
        diagnose::LabDataset d;
        std::vector<std::string> notes;
        try {
            d = io::parse_lab_dataset(req.body, format, &notes);
        } catch (const io::LabParseError& e) {
            auto err = unprocessable(std::string(io::lab_format_name(format)) + " upload: " + e.what());
            if (e.line > 0) err.at(e.line, e.column);
            if (!e.field.empty()) err.at_field(e.field);
            throw err;
        }
        // What is stored must read back: a reading that overflows when converted to SI
        // (e.g. 1e308 kPa) would be stored as null and break every later use of the dataset.
        try {
            io::parse_lab_json(io::lab_dataset_to_json(d));
        } catch (const io::LabParseError& e) {
            throw unprocessable(std::string(io::lab_format_name(format)) +
                                " upload: a value is out of range in SI units; stored it would read back as " + e.what())
                .at_field(e.field);
        }
        std::string name = req.has_param("name") ? req.get_param_value("name") : d.name;
        if (name.empty()) name = "dataset";
        check_resource_name(name, req.has_param("name") ? "query parameter 'name'" : "the dataset name in the file");
        d.name = name;
        const auto created = utc_now();
        const auto fmt = io::lab_format_name(format);
        const json header = header_columns(d);
        const std::string stored = io::lab_dataset_to_json(d).dump();
        const auto id = s.datasets.insert(name, fmt, stored, header, created);
        res.set_header("Location", "/datasets/" + std::to_string(id));
        auto out = dataset_header(DatasetRow{id, name, fmt, created, header}, header);
        out["notes"] = notes;  // what the reader inferred (kind of a stage, separator)
        send_json(res, out, 201);
    });
    s.route("GET", "/datasets", [&s](const httplib::Request& req, httplib::Response& res) {
        // The small header column only: no dataset is parsed under the lock.
        send_json(res, s.datasets.page(page_request(req), [](const DatasetRow& row) {
            return dataset_header(row, row.header.value_or(json::object()));
        }));
    });
    // The stored readings are sent as they are stored (they are the JSON upload form
    // already), read from the store in slices while the socket takes them: a 15 MB upload
    // is never parsed nor held whole to be read back.
    s.route("GET", R"(/datasets/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        const auto row = s.datasets.row(id);
        // A row stored before the header column and not yet filled: built from the readings.
        const json header = row.header ? *row.header : header_columns(load_dataset(s, id, nullptr));
        send_stored_member(s.db, res, dataset_header(row, header), "data", DatasetStore::readings(id));
    });
    s.route("DELETE", R"(/datasets/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        s.datasets.remove(path_id(req));
        res.status = 204;
    });
}

}  // namespace triax::service
