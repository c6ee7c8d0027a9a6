// SQLite store (migrations, WAL, foreign keys, prepared statements), the persisted event
// log, and the bounded job queue.
#include "server/events/event_log.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/store/database.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

using namespace triax::service;

namespace {
std::filesystem::path temp_dir(const std::string& tag) {
    std::mt19937_64 rng(std::random_device{}());
    auto p = std::filesystem::temp_directory_path() / ("triax-" + tag + "-" + std::to_string(rng()));
    std::filesystem::create_directories(p);
    return p;
}
const std::filesystem::path kMigrations = std::filesystem::path(TRIAX_SOURCE_DIR) / "schema" / "migrations";
}  // namespace

TEST_CASE("migrations apply once - WAL and foreign keys are on", "[server][store]") {
    const auto dir = temp_dir("store");
    {
        Database db(dir / "t.db", kMigrations);
        CHECK(db.schema_version() >= 1);
        db.with([](Database& d) {
            auto st = d.prepare("PRAGMA journal_mode");
            st.step();
            CHECK(st.text(0) == "wal");
            auto fk = d.prepare("PRAGMA foreign_keys");
            fk.step();
            CHECK(fk.int64(0) == 1);
            // A run must reference an existing scheme.
            auto bad = d.prepare("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (?, ?, 'queued', ?)");
            bad.bind_all(999, "x", utc_now());
            CHECK_THROWS_AS(bad.run(), StoreError);
        });
    }
    Database again(dir / "t.db", kMigrations);  // re-opening applies nothing twice
    CHECK(again.schema_version() >= 1);
    std::filesystem::remove_all(dir);
}

TEST_CASE("bound values are data, never SQL", "[server][store]") {
    const auto dir = temp_dir("inject");
    Database db(dir / "t.db", kMigrations);
    const std::string evil = "x'); DROP TABLE schemes; --";
    db.transaction([&](Database& d) {
        auto ins = d.prepare("INSERT INTO schemes(name, scheme_json, created_at) VALUES (?, ?, ?)");
        ins.bind_all(evil, "{}", utc_now());
        ins.run();
    });
    db.with([&](Database& d) {
        auto st = d.prepare("SELECT name FROM schemes");
        REQUIRE(st.step());
        CHECK(st.text(0) == evil);
    });
    std::filesystem::remove_all(dir);
}

TEST_CASE("a failed transaction leaves nothing behind", "[server][store]") {
    const auto dir = temp_dir("tx");
    Database db(dir / "t.db", kMigrations);
    CHECK_THROWS(db.transaction([](Database& d) {
        auto ins = d.prepare("INSERT INTO schemes(name, scheme_json, created_at) VALUES ('a', '{}', 'now')");
        ins.run();
        throw std::runtime_error("boom");
    }));
    db.with([](Database& d) {
        auto st = d.prepare("SELECT COUNT(*) FROM schemes");
        st.step();
        CHECK(st.int64(0) == 0);
    });
    std::filesystem::remove_all(dir);
}

TEST_CASE("event log: per-owner sequence, replay after an id, survives re-opening", "[server][store]") {
    const auto dir = temp_dir("events");
    {
        Database db(dir / "t.db", kMigrations);
        db.exec("INSERT INTO schemes(name, scheme_json, created_at) VALUES ('s', '{}', 'now')");
        db.exec("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 's', 'queued', 'now')");
        db.exec("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 's', 'queued', 'now')");
        EventLog log(db, "run_events", "run_id");
        CHECK(log.append(1, "status", {{"status", "running"}}) == 1);
        CHECK(log.append(1, "progress", {{"progress_pct", 10}}) == 2);
        CHECK(log.append(2, "status", {{"status", "running"}}) == 1);
        const auto after1 = log.since(1, 1, 100);
        REQUIRE(after1.size() == 1);
        CHECK(after1[0].type == "progress");
    }
    Database db(dir / "t.db", kMigrations);
    EventLog log(db, "run_events", "run_id");
    CHECK(log.append(1, "done", {{"status", "done"}}) == 3);  // continues after a restart
    CHECK(log.since(1, 0, 100).size() == 3);
    std::filesystem::remove_all(dir);
}

TEST_CASE("event log wait wakes on append and on shutdown", "[server][store]") {
    const auto dir = temp_dir("wait");
    Database db(dir / "t.db", kMigrations);
    db.exec("INSERT INTO schemes(name, scheme_json, created_at) VALUES ('s', '{}', 'now')");
    db.exec("INSERT INTO runs(scheme_id, name, status, created_at) VALUES (1, 's', 'queued', 'now')");
    EventLog log(db, "run_events", "run_id");
    std::thread writer([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        log.append(1, "status", {{"status", "running"}});
    });
    const auto t0 = std::chrono::steady_clock::now();
    log.wait(1, 0, std::chrono::seconds(10));
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5));
    writer.join();
    log.shutdown();
    log.wait(1, 99, std::chrono::seconds(10));  // returns at once
    CHECK(log.stopping());
    std::filesystem::remove_all(dir);
}

TEST_CASE("job queue: bounded, FIFO, withdraw, shutdown", "[server][jobs]") {
    JobQueue q(1, 2);
    std::atomic<bool> release{false};
    std::atomic<int> ran{0};
    std::vector<int> order;
    std::mutex m;
    REQUIRE(q.try_submit("a", [&] {
        while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        std::lock_guard l(m);
        order.push_back(0);
        ++ran;
    }));
    // Wait until the worker holds "a" so the queue has room for exactly two.
    for (int i = 0; i < 20000 && q.waiting() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    REQUIRE(q.try_submit("b", [&] { std::lock_guard l(m); order.push_back(1); ++ran; }));
    REQUIRE(q.try_submit("c", [&] { std::lock_guard l(m); order.push_back(2); ++ran; }));
    CHECK_FALSE(q.try_submit("d", [] {}));  // full -> the service answers 429
    CHECK(q.withdraw("b"));
    CHECK_FALSE(q.withdraw("b"));
    release = true;
    for (int i = 0; i < 20000 && ran < 2; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    CHECK(ran == 2);
    CHECK(order == std::vector<int>{0, 2});
    q.shutdown();
    CHECK_FALSE(q.try_submit("e", [] {}));
}
