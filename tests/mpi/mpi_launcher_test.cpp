// The service's MPI launcher (server/scaleout/mpi_job_launcher.hpp) with the real mpirun
// and triax CLI on the tiny DEM case of tests/mpi/data: progress and candidate lines reach
// the observer and the report file comes back; a bad option fails fast with the child's
// message; cancel ends mpirun and every rank (no process of the job is left).
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "server/io/lab_format.hpp"
#include "server/scaleout/mpi_job_launcher.hpp"

using namespace triax;
namespace fs = std::filesystem;

namespace {

struct Recorder : diagnose::DiagnoseObserver {
    std::vector<double> progress;
    int candidates = 0;
    bool cancel_when_running = false;  // cancel once the first progress line has come back
    void on_progress(double pct, std::string_view) override { progress.push_back(pct); }
    void on_candidate(const diagnose::CandidateResult& c) override { candidates += c.effect.empty() ? 0 : 1; }
    bool cancelled() const override { return cancel_when_running && !progress.empty(); }
};

nlohmann::json read_json(const fs::path& p) {
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}

scaleout::MpiDiagnosisInputs tiny_inputs() {
    const fs::path data = fs::path(TRIAX_SOURCE_DIR) / "tests/mpi/data";
    std::ifstream lab(data / "tiny_lab.csv");
    const std::string text((std::istreambuf_iterator<char>(lab)), std::istreambuf_iterator<char>());
    return {read_json(data / "tiny_scheme.json"), io::lab_dataset_to_json(io::parse_lab_csv(text)),
            read_json(data / "tiny_options.json")};
}

scaleout::MpiLaunchSettings settings(int ranks) {
    scaleout::MpiLaunchSettings s;
    s.ranks = ranks;
    s.triax = TRIAX_CLI_PATH;
    s.mpirun = MPIRUN_PATH;
    return s;
}

fs::path job_dir(const std::string& name) {
    const auto d = fs::temp_directory_path() / ("triax-mpi-launcher-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
}

// Processes whose command line names `dir` (mpirun and its ranks carry the input paths).
int processes_naming(const fs::path& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator("/proc")) {
        std::ifstream f(e.path() / "cmdline", std::ios::binary);
        if (!f) continue;
        const std::string cmd((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        if (cmd.find(dir.string()) != std::string::npos) ++n;
    }
    return n;
}

}  // namespace

TEST_CASE("an MPI diagnosis job streams progress and candidates and returns the report", "[mpi]") {
    // mpirun refuses root without these; the service's environment passes them on.
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1), setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    const auto dir = job_dir("report");
    Recorder rec;
    const auto report = scaleout::run_diagnosis_over_mpi(settings(2), dir, tiny_inputs(), rec);
    CHECK(report == read_json(dir / "report.json"));
    CHECK(report.contains("chosen_effect"));
    CHECK(report.value("runs_used", 0) > 0);
    REQUIRE(!rec.progress.empty());
    CHECK(rec.progress.back() == Approx(100.0));
    CHECK(std::is_sorted(rec.progress.begin(), rec.progress.end()));
    CHECK(rec.candidates > 0);
    fs::remove_all(dir);
}

TEST_CASE("an MPI diagnosis job with a bad option fails with the child's message", "[mpi]") {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1), setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    auto inputs = tiny_inputs();
    inputs.options["budget_runs"] = 2;
    Recorder rec;
    const auto dir = job_dir("bad");
    CHECK_THROWS_WITH(scaleout::run_diagnosis_over_mpi(settings(2), dir, inputs, rec),
                      Catch::Contains("budget_runs") && Catch::Contains("exit status"));
    CHECK(processes_naming(dir) == 0);
    fs::remove_all(dir);
}

TEST_CASE("cancelling an MPI diagnosis job ends mpirun and its ranks", "[mpi]") {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1), setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    Recorder rec;
    rec.cancel_when_running = true;
    // A job with many runs left when the first progress line comes back: the tiny case
    // alone can finish within one poll of the cancel flag.
    auto inputs = tiny_inputs();
    inputs.options["budget_runs"] = 40;
    const auto dir = job_dir("cancel");
    const auto t0 = std::chrono::steady_clock::now();
    CHECK_THROWS_AS(scaleout::run_diagnosis_over_mpi(settings(3), dir, inputs, rec), diagnose::DiagnosisCancelled);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(15));
    CHECK(processes_naming(dir) == 0);
    fs::remove_all(dir);
}
