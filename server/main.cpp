// triaxd: the REST service. Flags override environment (TRIAX_HOST, TRIAX_PORT,
// TRIAX_DATA_DIR, TRIAX_MPI_HOSTFILE, TRIAX_MPI_RANKS), which override the defaults
// (127.0.0.1:8080, ./data, diagnoses in this process). Prints the
// listening URL on stdout once the socket is bound (the browser test waits for it).
#include "server/runs/engine_executor.hpp"
#include "server/service.hpp"

#include <malloc.h>
#include <sys/resource.h>

#include <chrono>
#include <csignal>
#include <pthread.h>
#include <thread>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

namespace {

void usage() {
    std::cout << "usage: triaxd [--host H] [--port P] [--data-dir DIR] [--web-dir DIR] [--schema-dir DIR]\n"
                 "              [--workers N] [--threads-per-run N] [--queue-limit N] [--max-particles N]\n"
                 "              [--token T] [--allow-host NAME]... [--http-threads N] [--max-streams N] [--backlog N]\n"
                 "              [--head-timeout S] [--max-waiting N]\n"
                 "              [--mpi-hostfile FILE] [--mpi-ranks N] [--mpi-triax PATH]\n"
                 "env: TRIAX_HOST, TRIAX_PORT, TRIAX_DATA_DIR, TRIAX_TOKEN, TRIAX_MPI_HOSTFILE, TRIAX_MPI_RANKS\n"
                 "--mpi-ranks N > 0: each diagnosis runs as `mpirun [--hostfile FILE] -np N triax diagnose ...`\n"
                 "(--mpi-triax: the triax CLI, the same path on every host; default: next to triaxd)\n";
}

int to_int(const std::string& flag, const std::string& v) {
    try {
        std::size_t used = 0;
        const int n = std::stoi(v, &used);
        if (used != v.size()) throw std::invalid_argument(v);
        return n;
    } catch (const std::exception&) {
        throw std::invalid_argument(flag + " expects an integer, got '" + v + "'");
    }
}

}  // namespace

int main(int argc, char** argv) {
    // Buffers of 1 MiB and more (uploads, their parsed forms) are mapped and unmapped, so
    // their memory returns to the system when freed; with glibc's sliding threshold they
    // would come from the heaps of the HTTP threads and stay held there.
    mallopt(M_MMAP_THRESHOLD, 1 << 20);
    // Every waiting connection holds a descriptor (server/http/header_gate.hpp): take the
    // hard limit rather than a soft 1024.
    if (rlimit fds{}; getrlimit(RLIMIT_NOFILE, &fds) == 0 && fds.rlim_cur < fds.rlim_max) {
        fds.rlim_cur = fds.rlim_max;
        setrlimit(RLIMIT_NOFILE, &fds);
    }
    triax::service::ServiceConfig cfg;
    try {
        if (const char* e = std::getenv("TRIAX_HOST")) cfg.host = e;
        if (const char* e = std::getenv("TRIAX_PORT")) cfg.port = to_int("TRIAX_PORT", e);
        if (const char* e = std::getenv("TRIAX_DATA_DIR")) cfg.data_dir = e;
        if (const char* e = std::getenv("TRIAX_TOKEN")) cfg.token = e;
        if (const char* e = std::getenv("TRIAX_MPI_HOSTFILE")) cfg.mpi.hostfile = e;
        if (const char* e = std::getenv("TRIAX_MPI_RANKS")) cfg.mpi.ranks = to_int("TRIAX_MPI_RANKS", e);
        std::error_code ec;
        cfg.mpi.triax = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path() / "triax";
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "-h" || a == "--help") {
                usage();
                return 0;
            }
            if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value (or unknown flag)");
            const std::string v = argv[++i];
            if (a == "--host") cfg.host = v;
            else if (a == "--port") cfg.port = to_int(a, v);
            else if (a == "--data-dir") cfg.data_dir = v;
            else if (a == "--web-dir") cfg.web_dir = v;
            else if (a == "--schema-dir") cfg.schema_dir = v;
            else if (a == "--workers") cfg.workers = to_int(a, v);
            else if (a == "--threads-per-run") cfg.threads_per_run = to_int(a, v);
            else if (a == "--queue-limit") cfg.queue_limit = to_int(a, v);
            else if (a == "--max-particles") cfg.max_particles = to_int(a, v);
            else if (a == "--token") cfg.token = v;
            else if (a == "--allow-host") cfg.allowed_hosts.push_back(v);
            else if (a == "--http-threads") cfg.http_threads = to_int(a, v);
            else if (a == "--max-streams") cfg.max_event_streams = to_int(a, v);
            else if (a == "--backlog") cfg.listen_backlog = to_int(a, v);
            else if (a == "--head-timeout") cfg.head_timeout = std::chrono::seconds(to_int(a, v));
            else if (a == "--max-waiting") cfg.max_waiting_connections = to_int(a, v);
            else if (a == "--mpi-hostfile") cfg.mpi.hostfile = v;
            else if (a == "--mpi-ranks") cfg.mpi.ranks = to_int(a, v);
            else if (a == "--mpi-triax") cfg.mpi.triax = v;
            else throw std::invalid_argument("unknown flag " + a);
        }
        if (cfg.mpi.ranks < 0) throw std::invalid_argument("--mpi-ranks must be >= 0");
        if (cfg.mpi.enabled() && !cfg.mpi.hostfile.empty() && !std::filesystem::is_regular_file(cfg.mpi.hostfile))
            throw std::invalid_argument("--mpi-hostfile: no file " + cfg.mpi.hostfile.string());
        if (cfg.mpi.enabled() && !std::filesystem::is_regular_file(cfg.mpi.triax))
            throw std::invalid_argument("--mpi-triax: no triax CLI at " + cfg.mpi.triax.string());
    } catch (const std::exception& e) {
        std::cerr << "triaxd: " << e.what() << "\n";
        usage();
        return 2;
    }
    // SIGINT/SIGTERM are blocked in every thread and taken by one waiter thread, so the
    // stop runs as ordinary code rather than inside a signal handler.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
    try {
        triax::service::Service service(cfg, triax::service::make_engine_executor());
        std::thread waiter([&] {
            int sig = 0;
            sigwait(&stop_signals, &sig);
            // Jobs are interrupted and their streams get the terminal event before the
            // server stops; listen() below then returns.
            if (sig != 0) service.stop();
        });
        waiter.detach();
        service.bind();
        if (service.interrupted_at_start > 0)
            std::cerr << "triaxd: " << service.interrupted_at_start << " job(s) of the previous process marked interrupted\n";
        std::cout << "triaxd listening on " << service.url() << std::endl;
        const bool ok = service.listen();
        service.stop();
        return ok ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "triaxd: " << e.what() << "\n";
        return 1;
    }
}
