// The final model's schemes from the engine's DemForwardModel (see model_schemes.hpp).
#include "server/diagnoses/model_schemes.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/final_model.hpp"
#include "server/io/scheme_json.hpp"

namespace triax::service {

using nlohmann::json;
using namespace triax::diagnose;

namespace {

// A scheme name leaves room for the suffix within scheme_from_json's 200 bytes.
constexpr std::size_t kMaxBaseNameBytes = 150;

// The base name cut at a UTF-8 character boundary, then the condition.
std::string scheme_name(const std::string& base, double confining_pa) {
    std::size_t n = std::min(base.size(), kMaxBaseNameBytes);
    while (n > 0 && n < base.size() && (static_cast<unsigned char>(base[n]) & 0xC0) == 0x80) --n;
    std::ostringstream out;
    out << base.substr(0, n) << " (calibrated, " << confining_pa * 1e-3 << " kPa)";
    return out.str();
}

}  // namespace

json model_schemes_json(const protocol::TestScheme& scheme, const LabDataset& lab, const DiagnoseOptions& options,
                        const DiagnosisReport& report) {
    // As run_diagnosis builds it (dem_forward_model.cpp), without the cancel observer.
    const DemForwardModel model(scheme, lab, options);
    json out = json::array();
    for (const auto& run : model.engine_runs(final_model_point(model, report))) {
        protocol::TestScheme s = run.standalone_scheme();
        apply_fitted_artefacts(s, report.parameters);
        s.seed = options.seed;
        s.name = scheme_name(scheme.name, s.loading.confining_pressure_pa);
        json doc = io::scheme_to_json(s);
        io::scheme_from_json(doc);  // what POST /runs will do with it; throws SchemeError
        out.push_back({{"confining_kPa", s.loading.confining_pressure_pa * 1e-3}, {"scheme", std::move(doc)}});
    }
    return out;
}

}  // namespace triax::service
