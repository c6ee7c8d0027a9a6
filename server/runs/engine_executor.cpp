#include "server/runs/engine_executor.hpp"
#include "server/runs/series.hpp"

#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/packing_formats.hpp"
#include "server/io/result_json.hpp"
#include "server/io/scheme_json.hpp"

#include <chrono>

namespace triax::service {

using nlohmann::json;

namespace {

// The shear event also carries sigma1 and sigma3 so that the partial stress-strain series
// rebuilt from events has every column of the final one.
json shear_event(const protocol::ShearPoint& p) {
    json j = io::shear_point_to_json(p);
    j["sigma1_kPa"] = p.sigma1_pa * 1e-3;
    j["sigma3_kPa"] = p.sigma3_pa * 1e-3;
    return j;
}

// Streams what the engine reports. Progress is thinned to a few events per second: the
// engine may report every increment and each event is a database row.
class StreamingObserver : public protocol::RunObserver {
public:
    explicit StreamingObserver(RunContext& ctx) : ctx_(ctx) {}
    void progress(const std::string& stage, double fraction, double eta_s) override {
        const auto now = std::chrono::steady_clock::now();
        if (stage == last_stage_ && now - last_progress_ < std::chrono::milliseconds(250) && fraction < 1.0) return;
        last_progress_ = now;
        last_stage_ = stage;
        json d{{"stage", stage}, {"progress_pct", 100.0 * fraction}};
        d["eta_s"] = eta_s >= 0 ? json(eta_s) : json(nullptr);
        ctx_.emit("progress", d);
    }
    void stage_changed(const std::string& stage, int index, double stress_level, double q_target_pa) override {
        // The engine closes a cancelled run with "done" too; the run keeps the stage it
        // stopped in.
        if (stage == "done" && ctx_.cancel_requested()) return;
        json d{{"stage", stage}, {"index", index}};
        if (index > 0) {
            d["stress_level"] = stress_level;
            d["q_target_kPa"] = q_target_pa * 1e-3;
        }
        ctx_.emit("stage", d);
    }
    void shear_point(const protocol::ShearPoint& p) override { ctx_.emit("shear", shear_event(p)); }
    void creep_point(int stage, const protocol::CreepPoint& p) override { ctx_.emit("creep", io::creep_point_to_json(stage, p)); }
    void energy_sample(const protocol::EnergySample& e) override { ctx_.emit("energy", io::energy_sample_to_json(e)); }
    void measurement_sample(const protocol::MeasurementSample& m) override {
        ctx_.emit("measurement", io::measurement_sample_to_json(m));
    }
    void on_snapshot(const protocol::SpecimenSnapshot& s) override {
        if (ctx_.store_snapshot) ctx_.store_snapshot(io::snapshot_counts_json(s), io::encode_snapshot(s));
    }
    bool cancel_requested() override { return ctx_.cancel_requested(); }

private:
    RunContext& ctx_;
    std::string last_stage_;
    std::chrono::steady_clock::time_point last_progress_{};
};

}  // namespace

json result_document(const protocol::TestResult& r) {
    // server/io/result_json owns the lab-unit conversion; the store keeps each series as
    // rows in the columns of series_specs(), checked here so a drift fails loudly.
    const json full = io::result_to_json(r);
    json series = json::object();
    for (const auto& spec : series_specs()) {
        const json& s = full.at("series").at(spec.name);
        if (s.at("columns").get<std::vector<std::string>>() != spec.columns)
            throw std::logic_error(std::string("series '") + spec.name + "' columns differ from the service's");
        series[spec.name] = s.at("rows");
    }
    return {{"summary", full.at("summary")}, {"series", series}};
}

RunExecutor make_engine_executor() {
    return [](const json& scheme_json, RunContext& ctx) -> json {
        auto scheme = io::scheme_from_json(scheme_json);
        scheme.threads = ctx.threads;
        if (!ctx.packing.is_null())
            scheme.packing = std::make_shared<protocol::ImportedPacking>(io::packing_from_project_json(ctx.packing, "packing"));
        StreamingObserver observer(ctx);
        const auto result = protocol::run_triaxial_test(scheme, observer);
        if (result.cancelled) throw RunCancelled();
        return result_document(result);
    };
}

}  // namespace triax::service
