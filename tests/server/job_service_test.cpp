// The job lifecycle shared by runs, diagnoses and ensembles (server/jobs/job_service.hpp),
// with a scripted work on the `runs` table: queue -> run -> done, failure, cancel of a
// running and of a queued job, a full queue, a stop, and recovery at the next start.
#include "server/events/event_log.hpp"
#include "server/http/problem.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/jobs/job_service.hpp"
#include "server/store/database.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <thread>

using namespace triax::service;

namespace {

std::filesystem::path temp_dir() {
    std::mt19937_64 rng(std::random_device{}());
    auto p = std::filesystem::temp_directory_path() / ("triax-jobs-" + std::to_string(rng()));
    std::filesystem::create_directories(p);
    return p;
}
const std::filesystem::path kMigrations = std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "migrations";

// A work that waits for `release` (or its cancel flag), then fails or stores a stage.
struct ScriptedWork : JobWork {
    std::atomic<bool> release{false};
    std::atomic<bool> fail{false};
    std::atomic<int> started{0};
    std::set<std::int64_t> ran;
    std::mutex mutex;
    StoreResult run(std::int64_t id, const std::function<bool()>& cancelled) override {
        {
            std::lock_guard lock(mutex);
            ran.insert(id);
        }
        ++started;
        while (!release) {
            if (cancelled()) throw JobCancelled();
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        if (fail) throw std::runtime_error("the scripted work failed");
        return [id](Database& db) {
            auto up = db.prepare("UPDATE runs SET stage = 'done' WHERE id = ?");
            up.bind_all(id);
            up.run();
        };
    }
    bool has_run(std::int64_t id) {
        std::lock_guard lock(mutex);
        return ran.count(id) > 0;
    }
};

struct Fixture {
    std::filesystem::path dir = temp_dir();
    Database db{dir / "t.db", kMigrations};
    EventLog events{db, "run_events", "run_id"};
    ScriptedWork work;
    std::unique_ptr<JobQueue> queue = std::make_unique<JobQueue>(1, 1);
    JobService jobs{db, *queue, JobKind{"run", "runs", &events, true, ", eta_s = NULL", "re-run it"}, work};

    Fixture() { db.exec("INSERT INTO schemes(name, scheme_json, created_at) VALUES ('s', '{}', 'now')"); }
    ~Fixture() {
        work.release = true;
        queue->shutdown();
        std::filesystem::remove_all(dir);
    }
    std::int64_t submit() {
        return jobs.submit([](Database& db) {
            auto ins = db.prepare("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 's', 'queued', ?)");
            ins.bind_all(utc_now());
            ins.run();
            return db.last_insert_id();
        });
    }
    std::string error(std::int64_t id) {
        return db.with([&](Database& d) {
            auto st = d.prepare("SELECT error FROM runs WHERE id = ?");
            st.bind_all(id);
            st.step();
            return st.is_null(0) ? std::string("<null>") : st.text(0);
        });
    }
    std::vector<std::string> event_types(std::int64_t id) {
        std::vector<std::string> out;
        for (const auto& e : events.since(id, 0, 100)) out.push_back(e.type + (e.type == "status" ? ":" + nlohmann::json::parse(e.data).at("status").get<std::string>() : ""));
        return out;
    }
    bool wait_for(std::int64_t id, const std::string& status) {
        for (int i = 0; i < 10000; ++i) {
            if (jobs.state(id) == status) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return false;
    }
    void wait_started(int n) {
        for (int i = 0; i < 10000 && work.started < n; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
};

}  // namespace

TEST_CASE("job service: queued -> running -> done, the result stored with its done event", "[server][jobs]") {
    Fixture f;
    const auto id = f.submit();
    f.wait_started(1);
    CHECK(f.jobs.state(id) == "running");
    f.work.release = true;
    REQUIRE(f.wait_for(id, "done"));
    CHECK(f.event_types(id) == std::vector<std::string>{"status:queued", "status:running", "done"});
    CHECK(f.error(id) == "<null>");
    f.db.with([&](Database& d) {
        auto st = d.prepare("SELECT stage, started_at IS NOT NULL, finished_at IS NOT NULL FROM runs WHERE id = ?");
        st.bind_all(id);
        REQUIRE(st.step());
        CHECK(st.text(0) == "done");
        CHECK(st.int64(1) == 1);
        CHECK(st.int64(2) == 1);
    });
    CHECK_THROWS_AS(f.jobs.cancel(id), ApiError);  // 409: it has ended
    CHECK_NOTHROW(f.jobs.require_ended(id));
}

TEST_CASE("job service: a work that throws ends the job failed with its text", "[server][jobs]") {
    Fixture f;
    f.work.fail = true;
    f.work.release = true;
    const auto id = f.submit();
    REQUIRE(f.wait_for(id, "failed"));
    CHECK(f.error(id) == "the scripted work failed");
    CHECK(f.event_types(id).back() == "error");
}

TEST_CASE("job service: cancel a running job, then a queued one - a full queue keeps nothing", "[server][jobs]") {
    Fixture f;
    const auto running = f.submit();
    f.wait_started(1);
    const auto waiting = f.submit();
    // One worker busy, one job waiting: the queue (limit 1) is full.
    try {
        f.submit();
        FAIL("the third job was accepted");
    } catch (const ApiError& e) {
        CHECK(e.status == 429);
    }
    f.db.with([&](Database& d) {
        auto st = d.prepare("SELECT COUNT(*) FROM runs");
        st.step();
        CHECK(st.int64(0) == 2);
    });
    CHECK_THROWS_AS(f.jobs.require_ended(waiting), ApiError);  // 409 while queued

    f.jobs.cancel(waiting);  // withdrawn from the queue: ends at once
    CHECK(f.jobs.state(waiting) == "cancelled");
    CHECK(f.error(waiting) == "cancelled by request before it started");
    f.jobs.cancel(running);  // stops at its next poll
    REQUIRE(f.wait_for(running, "cancelled"));
    CHECK(f.error(running) == "cancelled by request");
    CHECK(f.event_types(running).back() == "error");
    CHECK_FALSE(f.work.has_run(waiting));
    try {
        f.jobs.cancel(12345);
        FAIL("an unknown job was cancelled");
    } catch (const ApiError& e) {
        CHECK(e.status == 404);
        CHECK(std::string(e.what()) == "run 12345 does not exist");
    }
}

TEST_CASE("job service: a stop interrupts the running job - the next start interrupts what was left", "[server][jobs]") {
    Fixture f;
    const auto running = f.submit();
    f.wait_started(1);
    const auto waiting = f.submit();
    f.jobs.begin_shutdown();
    REQUIRE(f.wait_for(running, "interrupted"));
    CHECK(f.error(running) == "the service stopped during the run; re-run it");
    f.queue->shutdown();  // drops the waiting job unless the worker took it (then it was interrupted)
    const auto left = f.jobs.state(waiting);
    CHECK((left == "queued" || left == "interrupted"));
    // A process killed with kill -9 leaves its running job as it was.
    f.db.exec("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 's', 'running', 'now')");
    const auto killed = f.db.with([](Database& d) { return d.last_insert_id(); });

    // The next process: jobs left queued or running by the last one are interrupted.
    ScriptedWork work;
    JobQueue queue(1, 4);
    JobService next(f.db, queue, JobKind{"run", "runs", &f.events, true, ", eta_s = NULL", "re-run it"}, work);
    CHECK(next.recover_interrupted() == (left == "queued" ? 2 : 1));
    CHECK(next.state(waiting) == "interrupted");
    CHECK(next.state(killed) == "interrupted");
    CHECK(f.error(killed) == "the service stopped before the run ended; re-run it");
    CHECK(f.event_types(killed).back() == "error");
    CHECK_NOTHROW(next.require_ended(killed));
    CHECK(next.recover_interrupted() == 0);
    CHECK(work.started == 0);
    queue.shutdown();
}
