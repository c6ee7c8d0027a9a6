// libFuzzer targets, one per parser that reads outside input. Each accepts the parser's
// documented refusals (its error type naming the field, line or pointer) and nothing
// else: any other exception, a crash, a hang or a sanitizer report is a finding.
// Built once per target with -DTRIAX_FUZZ_TARGET=<n> (tests/fuzz/CMakeLists.txt).
#include "engine/core/types.hpp"
#include "server/io/bounded_json.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/lab_format.hpp"
#include "server/io/scheme_json.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace {

using namespace triax;

std::string_view text_of(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

void scheme_json(std::string_view text) {
    try {
        const auto doc = io::parse_bounded_json(text);
        const auto scheme = io::scheme_from_json(doc);
        // What is accepted must serialise and read back.
        (void)io::scheme_from_json(io::scheme_to_json(scheme));
    } catch (const io::JsonLimitError&) {
    } catch (const io::SchemeError&) {
    }
}

void lab(std::string_view text, io::LabFormat format) {
    try {
        std::vector<std::string> notes;
        const auto d = io::parse_lab_dataset(text, format, &notes);
        (void)io::lab_curve_index(d);
        // The service refuses an upload that is not UTF-8 before parsing it (dataset_routes.cpp);
        // here the bytes reach the parser, so the dump replaces them as send_json does.
        (void)io::lab_dataset_to_json(d).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    } catch (const io::LabParseError&) {
    }
}

void diagnose_options(std::string_view text) {
    try {
        const auto o = io::diagnose_options_from_json(io::parse_bounded_json(text));
        (void)io::diagnose_options_from_json(io::diagnose_options_to_json(o));
    } catch (const io::JsonLimitError&) {
    } catch (const io::DiagnosisRequestError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto text = text_of(data, size);
#if TRIAX_FUZZ_TARGET == 1
    scheme_json(text);
#elif TRIAX_FUZZ_TARGET == 2
    lab(text, io::LabFormat::Csv);
#elif TRIAX_FUZZ_TARGET == 3
    lab(text, io::LabFormat::Gds);
#elif TRIAX_FUZZ_TARGET == 4
    lab(text, io::LabFormat::Ags);
#elif TRIAX_FUZZ_TARGET == 5
    lab(text, io::LabFormat::Json);
#elif TRIAX_FUZZ_TARGET == 6
    diagnose_options(text);
#else
#error "TRIAX_FUZZ_TARGET must be 1..6"
#endif
    return 0;
}
