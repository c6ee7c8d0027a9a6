#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "server/cli/commands.hpp"
#include "server/io/bounded_json.hpp"
#include "server/io/lab_format.hpp"
#include "server/io/scheme_json.hpp"

namespace triax::cli {

namespace {

std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::invalid_argument("cannot open " + path);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

}  // namespace

protocol::TestScheme read_scheme_file(const std::string& path) {
    nlohmann::json j;
    try {
        j = io::parse_bounded_json(read_text(path));  // depth, size and duplicate-key limits
    } catch (const io::JsonLimitError& e) {
        throw std::invalid_argument(path + ": " + (e.pointer.empty() ? "" : "field " + e.pointer + ": ") + e.what());
    } catch (const nlohmann::json::parse_error& e) {
        throw std::invalid_argument(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
    }
    try {
        return io::scheme_from_json(j);
    } catch (const io::SchemeError& e) {
        throw std::invalid_argument(path + ": field " + e.field + ": " + e.what());
    }
}

diagnose::LabDataset read_lab_file(const std::string& path, const std::string& format) {
    const std::string text = read_text(path);
    io::LabFormat f;
    if (format.empty()) {
        f = io::sniff_lab_format(text);
    } else {
        const auto named = io::lab_format_from_name(format);
        if (!named) throw std::invalid_argument("--format must be one of csv, gds, ags, json; got '" + format + "'");
        f = *named;
    }
    try {
        return io::parse_lab_dataset(text, f);
    } catch (const io::LabParseError& e) {
        throw std::invalid_argument(path + " (" + io::lab_format_name(f) + "): " + e.what());
    }
}

}  // namespace triax::cli
