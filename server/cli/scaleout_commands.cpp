// `triax diagnose` and `triax ensemble`: forward runs on threads of this process, or, when
// started by `mpirun -np N`, on the N ranks of the job (server/scaleout). Every rank reads
// the same input files and builds the same model; rank 0 runs the loop, writes the output
// and prints progress on stderr as lines the service reads (mpi_job_launcher.hpp):
//   progress <percent> <stage>
//   candidate <one-line JSON of the candidate event>
// The report is the same whatever the number of ranks (simulation_batch.hpp).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/diagnose/dem_forward_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "server/cli/commands.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/io/ensemble_json.hpp"
#include "server/scaleout/ensemble.hpp"
#include "server/scaleout/task_runner.hpp"
#ifdef TRIAX_WITH_MPI
#include "server/scaleout/mpi_simulation_batch.hpp"
#include "server/scaleout/mpi_task_pool.hpp"
#endif

namespace triax::cli {

namespace {

bool under_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
           std::getenv("PMI_RANK") != nullptr;
}

// The ranks of this mpirun job (pool null: no mpirun, the runs go to threads).
struct Ranks {
#ifdef TRIAX_WITH_MPI
    std::unique_ptr<scaleout::MpiSession> session;
    std::unique_ptr<scaleout::MpiTaskPool> pool;  // destroyed first: rank 0 stops the others
#endif
    bool mpi() const {
#ifdef TRIAX_WITH_MPI
        return pool != nullptr;
#else
        return false;
#endif
    }
    bool root() const {
#ifdef TRIAX_WITH_MPI
        return !pool || pool->is_root();
#else
        return true;
#endif
    }
    int size() const {
#ifdef TRIAX_WITH_MPI
        return pool ? pool->size() : 1;
#else
        return 1;
#endif
    }
    // Collective: every rank could read its inputs. A rank that could not says why on
    // stderr; all ranks then stop (none is left serving a rank 0 that gave up).
    bool all_ok(bool ok) const {
#ifdef TRIAX_WITH_MPI
        return pool ? pool->all_ok(ok) : ok;
#else
        return ok;
#endif
    }
};

Ranks join_ranks(int& argc, char**& argv) {
    Ranks r;
    if (!under_mpirun()) return r;
#ifdef TRIAX_WITH_MPI
    r.session = std::make_unique<scaleout::MpiSession>(argc, argv);
    r.pool = std::make_unique<scaleout::MpiTaskPool>();
#else
    throw std::runtime_error("this triax was built without MPI (install libopenmpi-dev and rebuild)");
#endif
    return r;
}

struct Args {
    int argc;
    char** argv;
    int i = 2;
    std::string value(const std::string& flag) {
        if (i + 1 >= argc) throw std::invalid_argument(flag + " needs a value");
        return argv[++i];
    }
};

int to_int(const std::string& flag, const std::string& v, int lo, int hi) {
    std::size_t used = 0;
    int n = 0;
    try {
        n = std::stoi(v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v.size() || v.empty() || n < lo || n > hi)
        throw std::invalid_argument(flag + " expects an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                    "], got '" + v + "'");
    return n;
}

void write_file(const std::filesystem::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    if (!f || !(f << text)) throw std::runtime_error("cannot write " + p.string());
}

class StderrDiagnoseObserver final : public diagnose::DiagnoseObserver {
public:
    void on_progress(double percent, std::string_view stage) override {
        std::fprintf(stderr, "progress %.1f %.*s\n", percent, static_cast<int>(stage.size()), stage.data());
        std::fflush(stderr);
    }
    void on_candidate(const diagnose::CandidateResult& c) override {
        std::fprintf(stderr, "candidate %s\n", io::candidate_to_json(c).dump().c_str());
        std::fflush(stderr);
    }
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int diagnose_command(int argc, char** argv) {
    std::string scheme_path, lab_path, format, options_path, out;
    for (Args a{argc, argv}; a.i < argc; ++a.i) {
        const std::string f = argv[a.i];
        if (f == "--scheme") scheme_path = a.value(f);
        else if (f == "--dataset") lab_path = a.value(f);
        else if (f == "--format") format = a.value(f);
        else if (f == "--options") options_path = a.value(f);
        else if (f == "--out") out = a.value(f);
        else throw std::invalid_argument("unknown option " + f);
    }
    if (scheme_path.empty() || lab_path.empty()) throw std::invalid_argument("diagnose needs --scheme and --dataset");
    const auto t0 = std::chrono::steady_clock::now();
    Ranks ranks = join_ranks(argc, argv);

    protocol::TestScheme scheme;
    diagnose::LabDataset lab;
    diagnose::DiagnoseOptions options;
    std::string input_error;
    try {
        scheme = read_scheme_file(scheme_path);
        lab = read_lab_file(lab_path, format);
        if (!options_path.empty()) {
            std::ifstream f(options_path);
            if (!f) throw std::invalid_argument("cannot open " + options_path);
            nlohmann::json j;
            try {
                j = nlohmann::json::parse(f);
            } catch (const nlohmann::json::parse_error& e) {
                throw std::invalid_argument(options_path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
            }
            try {
                options = io::diagnose_options_from_json(j);
            } catch (const io::DiagnosisRequestError& e) {
                throw std::invalid_argument(options_path + ": field " + e.field + ": " + e.what());
            }
        }
    } catch (const std::exception& e) {
        input_error = e.what();
    }
    if (!ranks.all_ok(input_error.empty())) {
        if (!input_error.empty()) throw std::invalid_argument(input_error);
        if (ranks.root()) throw std::invalid_argument("another rank could not read the inputs (its message is above)");
        return 2;
    }
    // Every rank builds the same model from the same files (no cancel: the service ends an
    // MPI diagnosis by ending mpirun).
    const diagnose::DemForwardModel model(scheme, lab, options);
    StderrDiagnoseObserver observer;
    diagnose::DiagnosisReport report;
    if (!ranks.mpi()) {
        report = diagnose::run_diagnosis(lab, model, options, observer);
    } else {
#ifdef TRIAX_WITH_MPI
        if (!ranks.root()) {
            scaleout::MpiSimulationBatch::serve(*ranks.pool, model);
            return 0;
        }
        scaleout::MpiSimulationBatch batch(*ranks.pool);
        // The calibration sizes its batches by options.batch_runs, not by the ranks, so
        // the report does not depend on -np; more ranks than that number wait.
        if (options.batch_runs < batch.width())
            std::fprintf(stderr, "diagnose: batch_runs %d < %d ranks: set \"batch_runs\" in the options to use them all\n",
                         options.batch_runs, batch.width());
        report = diagnose::run_diagnosis(lab, model, options, observer, batch);
#endif
    }
    const std::string doc = io::diagnosis_report_to_json(report).dump(2) + "\n";
    if (out.empty()) std::cout << doc;
    else write_file(out, doc);
    std::fprintf(stderr, "diagnose: %s, %d runs, %d rank(s), wall time %.1f s\n", report.chosen_effect.c_str(),
                 report.runs_used, ranks.size(), seconds_since(t0));
    return 0;
}

int ensemble_command(int argc, char** argv) {
    std::string scheme_path, seeds_text, out = "triax-ensemble";
    int concurrency = 1, threads = 0, max_particles = -1;
    for (Args a{argc, argv}; a.i < argc; ++a.i) {
        const std::string f = argv[a.i];
        if (f == "--scheme") scheme_path = a.value(f);
        else if (f == "--seeds") seeds_text = a.value(f);
        else if (f == "--out") out = a.value(f);
        else if (f == "--concurrency") concurrency = to_int(f, a.value(f), 1, 64);
        else if (f == "--threads") threads = to_int(f, a.value(f), 1, 64);
        else if (f == "--max-particles") max_particles = to_int(f, a.value(f), 0, 1000000);
        else throw std::invalid_argument("unknown option " + f);
    }
    if (scheme_path.empty() || seeds_text.empty()) throw std::invalid_argument("ensemble needs --scheme and --seeds");
    const auto t0 = std::chrono::steady_clock::now();
    Ranks ranks = join_ranks(argc, argv);

    protocol::TestScheme scheme;
    std::vector<std::uint64_t> seeds;
    std::string input_error;
    try {
        scheme = read_scheme_file(scheme_path);
        seeds = scaleout::parse_seed_list(seeds_text);
    } catch (const std::exception& e) {
        input_error = e.what();
    }
    if (!ranks.all_ok(input_error.empty())) {
        if (!input_error.empty()) throw std::invalid_argument(input_error);
        if (ranks.root()) throw std::invalid_argument("another rank could not read the inputs (its message is above)");
        return 2;
    }
    if (threads > 0) scheme.threads = threads;
    if (max_particles >= 0) scheme.max_particles = max_particles;
    const scaleout::TaskHandler handler = scaleout::member_handler(scheme);
#ifdef TRIAX_WITH_MPI
    if (ranks.mpi() && !ranks.root()) {
        ranks.pool->serve(handler);
        return 0;
    }
#endif
    std::vector<std::string> tasks;
    for (auto s : seeds) tasks.push_back(scaleout::member_task(s));
    std::mutex progress_mutex;
    std::size_t finished = 0;
    const auto on_done = [&](std::size_t i) {
        std::lock_guard lock(progress_mutex);
        ++finished;
        std::fprintf(stderr, "progress %.1f ensemble: seed %llu done (%zu of %zu)\n",
                     100.0 * static_cast<double>(finished) / static_cast<double>(tasks.size()),
                     static_cast<unsigned long long>(seeds[i]), finished, tasks.size());
        std::fflush(stderr);
    };
    std::vector<scaleout::TaskResult> results;
#ifdef TRIAX_WITH_MPI
    if (ranks.mpi()) results = ranks.pool->run(tasks, handler, on_done);
#endif
    if (!ranks.mpi()) results = scaleout::run_tasks_in_threads(tasks, handler, concurrency, on_done);
    std::vector<diagnose::EnsembleMember> members;
    for (std::size_t i = 0; i < seeds.size(); ++i) members.push_back(scaleout::member_from_result(seeds[i], results[i]));
    const auto summary = diagnose::summarise_ensemble(scheme.name, std::move(members));
    std::filesystem::create_directories(out);
    write_file(std::filesystem::path(out) / "ensemble.json", io::ensemble_to_json(summary, true).dump(2) + "\n");
    write_file(std::filesystem::path(out) / "shear_band.csv", io::shear_band_csv(summary));
    write_file(std::filesystem::path(out) / "creep_band.csv", io::creep_band_csv(summary));
    std::cout << io::ensemble_to_json(summary, false).dump(2) << "\n";
    std::fprintf(stderr, "ensemble: %d of %zu seeds ran, %d rank(s), wall time %.1f s\n", summary.ok, seeds.size(),
                 ranks.size(), seconds_since(t0));
    return summary.ok == static_cast<int>(seeds.size()) ? 0 : 1;
}

}  // namespace triax::cli
