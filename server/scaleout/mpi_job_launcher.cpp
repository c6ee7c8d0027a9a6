#include "server/scaleout/mpi_job_launcher.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <vector>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "server/io/diagnosis_json.hpp"

extern char** environ;

namespace triax::scaleout {

namespace {

void write_json(const std::filesystem::path& p, const nlohmann::json& j) {
    std::ofstream f(p, std::ios::binary);
    if (!f || !(f << j.dump() << "\n")) throw std::runtime_error("cannot write " + p.string());
}

// The child, its own process group, and its stderr pipe.
class Child {
public:
    explicit Child(const std::vector<std::string>& argv) {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
        read_fd_ = fds[0];
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_adddup2(&fa, fds[1], 2);
        posix_spawnattr_t at;
        posix_spawnattr_init(&at);
        // Own process group (cancel ends mpirun and its local ranks together); the service
        // blocks SIGINT/SIGTERM in its threads (main.cpp), so the child gets them unblocked
        // and at their defaults.
        sigset_t none, defaults;
        sigemptyset(&none);
        sigemptyset(&defaults);
        for (int sig : {SIGINT, SIGTERM, SIGPIPE, SIGHUP}) sigaddset(&defaults, sig);
        posix_spawnattr_setpgroup(&at, 0);
        posix_spawnattr_setsigmask(&at, &none);
        posix_spawnattr_setsigdefault(&at, &defaults);
        posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        const int rc = posix_spawnp(&pid_, args[0], &fa, &at, args.data(), environ);
        posix_spawn_file_actions_destroy(&fa);
        posix_spawnattr_destroy(&at);
        close(fds[1]);
        if (rc != 0) {
            close(read_fd_);
            throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
        }
    }
    ~Child() {
        if (pid_ > 0) stop();
        close(read_fd_);
    }
    int read_fd() const { return read_fd_; }

    // Exit status once ended (waitpid), or nullopt while running.
    bool ended(int& status) {
        if (pid_ <= 0) return status = status_, true;
        const pid_t r = waitpid(pid_, &status_, WNOHANG);
        if (r == pid_) {
            pid_ = -1;
            status = status_;
            return true;
        }
        return false;
    }
    void stop() {
        if (pid_ <= 0) return;
        kill(-pid_, SIGTERM);
        int status = 0;
        for (int i = 0; i < 50; ++i) {
            if (ended(status)) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        kill(-pid_, SIGKILL);
        waitpid(pid_, &status_, 0);
        pid_ = -1;
    }

private:
    pid_t pid_ = -1;
    int read_fd_ = -1;
    int status_ = 0;
};

std::string describe_status(int status) {
    if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
    return "status " + std::to_string(status);
}

}  // namespace

std::vector<std::string> mpi_diagnosis_command(const MpiLaunchSettings& s, const std::filesystem::path& dir) {
    std::vector<std::string> cmd{s.mpirun};
    if (!s.hostfile.empty()) cmd.insert(cmd.end(), {"--hostfile", s.hostfile.string()});
    cmd.insert(cmd.end(), {"-np", std::to_string(s.ranks), s.triax.string(), "diagnose",
                           "--scheme", (dir / "scheme.json").string(),
                           "--dataset", (dir / "dataset.json").string(), "--format", "json",
                           "--options", (dir / "options.json").string(),
                           "--out", (dir / "report.json").string()});
    return cmd;
}

nlohmann::json run_diagnosis_over_mpi(const MpiLaunchSettings& settings, const std::filesystem::path& job_dir,
                                      const MpiDiagnosisInputs& inputs, diagnose::DiagnoseObserver& observer) {
    // Absolute paths on the command line: the ranks on other hosts read the same files.
    const auto dir = std::filesystem::absolute(job_dir);
    std::filesystem::create_directories(dir);
    write_json(dir / "scheme.json", inputs.scheme);
    write_json(dir / "dataset.json", inputs.dataset);
    write_json(dir / "options.json", inputs.options.is_null() ? nlohmann::json::object() : inputs.options);
    std::filesystem::remove(dir / "report.json");

    Child child(mpi_diagnosis_command(settings, dir));
    std::string pending;
    // The child's lines that are not progress: the first few (a rank's own error comes
    // first) and the last few (mpirun's summary of how the job ended).
    std::vector<std::string> first;
    std::deque<std::string> other;
    long dropped = 0;
    auto take_line = [&](const std::string& line) {
        if (line.rfind("progress ", 0) == 0) {
            std::istringstream in(line.substr(9));
            double pct = 0.0;
            std::string stage;
            if (in >> pct) {
                std::getline(in >> std::ws, stage);
                observer.on_progress(pct, stage);
                return;
            }
        } else if (line.rfind("candidate ", 0) == 0) {
            try {
                observer.on_candidate(io::candidate_from_json(nlohmann::json::parse(line.substr(10))));
                return;
            } catch (const std::exception&) {
                // not a candidate line after all: kept below
            }
        }
        if (first.size() < 6) {
            first.push_back(line);
            return;
        }
        other.push_back(line);
        if (other.size() > 12) {
            other.pop_front();
            ++dropped;
        }
    };
    bool open = true;
    int status = 0;
    for (;;) {
        if (observer.cancelled()) {
            child.stop();
            throw diagnose::DiagnosisCancelled{};
        }
        if (open) {
            pollfd p{child.read_fd(), POLLIN, 0};
            if (poll(&p, 1, 250) > 0) {
                char buf[4096];
                const ssize_t n = read(child.read_fd(), buf, sizeof buf);
                if (n <= 0) {
                    open = false;
                } else {
                    pending.append(buf, static_cast<std::size_t>(n));
                    for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
                        take_line(pending.substr(0, nl));
                        pending.erase(0, nl + 1);
                    }
                }
            }
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        if (!open && child.ended(status)) break;
    }
    if (!pending.empty()) take_line(pending);
    std::ifstream report(dir / "report.json");
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0) || !report) {
        std::string tail;
        for (const auto& l : first) tail += (tail.empty() ? "" : " | ") + l;
        if (dropped > 0) tail += " | (" + std::to_string(dropped) + " lines left out)";
        for (const auto& l : other) tail += (tail.empty() ? "" : " | ") + l;
        throw std::runtime_error("the MPI diagnosis (" + settings.mpirun + " -np " + std::to_string(settings.ranks) +
                                 ") ended with " + describe_status(status) + (tail.empty() ? "" : ": " + tail));
    }
    return nlohmann::json::parse(report);
}

}  // namespace triax::scaleout
