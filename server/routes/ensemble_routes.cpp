// POST /ensembles, GET /ensembles, GET /ensembles/{id}, POST /ensembles/{id}/cancel,
// GET /ensembles/{id}/shear_band.csv, GET /ensembles/{id}/creep_band.csv. The scheme comes
// as POST /runs takes it (inline, stored first, or by id); the job is EnsembleService's.
#include "server/ensembles/ensemble_service.hpp"
#include "server/http/problem.hpp"
#include "server/scaleout/ensemble.hpp"
#include "server/service.hpp"

#include <cstdint>

namespace triax::service {

using nlohmann::json;

namespace {

// The seed list of the body: a string in parse_seed_list syntax ("1-8", "3", "1,4,9-12")
// naming 1 to kMaxSeeds seeds; anything else is 422 naming /seeds.
std::vector<std::uint64_t> body_seeds(const json& body) {
    if (!body.contains("seeds")) throw unprocessable("'seeds' is required, e.g. \"1-8\"").at_field("/seeds");
    if (!body["seeds"].is_string())
        throw unprocessable("seeds must be a string such as \"1-8\" or \"1,4,9-12\"").at_field("/seeds");
    std::vector<std::uint64_t> seeds;
    try {
        seeds = scaleout::parse_seed_list(body["seeds"].get<std::string>());
    } catch (const std::invalid_argument& e) {
        // The parser speaks to the CLI ("--seeds: ..."); the field is named by the pointer.
        std::string detail = e.what();
        if (detail.rfind("--seeds: ", 0) == 0) detail.erase(0, 9);
        throw unprocessable("seeds: " + detail).at_field("/seeds");
    }
    constexpr auto kMax = EnsembleService::kMaxSeeds;
    if (seeds.size() > kMax)
        throw unprocessable("seeds names " + std::to_string(seeds.size()) + " seeds; an ensemble runs at most " +
                            std::to_string(kMax))
            .at_field("/seeds")
            .with_limit("seeds <= " + std::to_string(kMax));
    return seeds;
}

void send_csv(httplib::Response& res, const std::string& text) {
    res.status = 200;
    res.set_content(text, "text/csv");
}

}  // namespace

void register_ensemble_routes(Service& s) {
    s.route("POST", "/ensembles", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto body = parse_body(req);
        if (!body.is_object())
            throw unprocessable("the body must be an object with 'seeds' and 'scheme' or 'scheme_id'").at_field("");
        for (const auto& [k, v] : body.items())
            if (k != "scheme" && k != "scheme_id" && k != "seeds" && k != "concurrency")
                throw unprocessable("unknown field '" + k + "' (scheme, scheme_id, seeds, concurrency)").at_field("/" + k);
        const bool inline_scheme = body.contains("scheme"), by_id = body.contains("scheme_id");
        if (inline_scheme == by_id) throw unprocessable("give exactly one of 'scheme' or 'scheme_id'").at_field("/scheme");
        // Everything but the scheme is checked before an inline scheme is stored: a refused
        // request leaves nothing behind.
        const auto seeds = body_seeds(body);
        std::optional<int> concurrency;
        if (body.contains("concurrency"))
            concurrency = static_cast<int>(body_integer(body["concurrency"], "/concurrency", 1, s.config.max_threads_per_run));
        std::int64_t scheme_id = 0;
        if (by_id) {
            scheme_id = body_integer(body["scheme_id"], "/scheme_id", 1, INT64_MAX);
        } else {
            scheme_id = store_scheme(s, body["scheme"], "/scheme")["id"].get<std::int64_t>();
        }
        auto out = s.ensembles.submit(scheme_id, body["seeds"].get<std::string>(), seeds.size(), concurrency);
        out["scheme_id"] = scheme_id;
        out["members_total"] = seeds.size();
        res.set_header("Location", "/ensembles/" + std::to_string(out["id"].get<std::int64_t>()));
        send_json(res, out, 202);
    });
    s.route("GET", "/ensembles", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.ensembles.list(page_request(req, true)));
    });
    s.route("GET", R"(/ensembles/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.ensembles.status(path_id(req)));
    });
    s.route("POST", R"(/ensembles/([^/]+)/cancel)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        s.ensembles.cancel(id);
        send_json(res, {{"id", id}, {"status", "cancelling"}}, 202);
    });
    s.route("GET", R"(/ensembles/([^/]+)/shear_band\.csv)", [&s](const httplib::Request& req, httplib::Response& res) {
        send_csv(res, s.ensembles.band_csv(path_id(req), "shear_band"));
    }, "/ensembles/{id}/shear_band.csv");
    s.route("GET", R"(/ensembles/([^/]+)/creep_band\.csv)", [&s](const httplib::Request& req, httplib::Response& res) {
        send_csv(res, s.ensembles.band_csv(path_id(req), "creep_band"));
    }, "/ensembles/{id}/creep_band.csv");
}

}  // namespace triax::service
