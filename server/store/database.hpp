#pragma once
// Thin RAII layer over one SQLite connection: prepared statements only (values are always
// bound, never spliced into SQL), WAL journal, foreign keys on, and schema migrations read
// from schema/migrations/NNN_*.sql applied in order at open. One connection is shared by
// the HTTP threads and the workers; every use goes through `with()` which holds its mutex,
// so callers never see a half-finished transaction of another thread.
#include "server/store/not_found.hpp"

#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace triax::service {

// A storage failure (disk full, corrupt file, constraint): the HTTP layer maps it to 500/507.
struct StoreError : std::runtime_error {
    int code;
    StoreError(const std::string& what, int c) : std::runtime_error(what), code(c) {}
};

// Bytes stored as a BLOB (a std::string binds as TEXT).
struct Blob {
    std::string bytes;
};

using SqlValue = std::variant<std::nullptr_t, std::int64_t, double, std::string, Blob>;

class Statement {
public:
    Statement(sqlite3* db, std::string_view sql);
    ~Statement();
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    // Binds 1-based parameters in order.
    Statement& bind(int index, const SqlValue& v);
    template <class... A> Statement& bind_all(const A&... args) {
        int i = 1;
        (bind(i++, to_value(args)), ...);
        return *this;
    }
    // Steps once; true while a row is available.
    bool step();
    // Runs to completion (for INSERT/UPDATE/DELETE).
    void run();

    std::int64_t int64(int col) const;
    double real(int col) const;
    std::string text(int col) const;
    std::string blob(int col) const;
    bool is_null(int col) const;

private:
    static SqlValue to_value(std::nullptr_t) { return nullptr; }
    static SqlValue to_value(int v) { return std::int64_t{v}; }
    static SqlValue to_value(long v) { return std::int64_t{v}; }
    static SqlValue to_value(long long v) { return std::int64_t{v}; }
    static SqlValue to_value(double v) { return v; }
    static SqlValue to_value(const std::string& v) { return v; }
    static SqlValue to_value(const char* v) { return std::string(v); }
    static SqlValue to_value(std::string_view v) { return std::string(v); }
    static SqlValue to_value(const Blob& v) { return v; }
    template <class T> static SqlValue to_value(const std::optional<T>& v) {
        return v ? to_value(*v) : SqlValue{nullptr};
    }
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

class Database {
public:
    // Opens (creating if needed) the file and applies pending migrations from `migrations_dir`.
    Database(const std::filesystem::path& file, const std::filesystem::path& migrations_dir);
    ~Database();
    Database(const Database&) = delete;
    Database& operator=(const Database&) = delete;

    // Runs `fn` with exclusive use of the connection.
    template <class F> auto with(F&& fn) {
        std::lock_guard lock(mutex_);
        return fn(*this);
    }
    // Runs `fn` inside BEGIN IMMEDIATE ... COMMIT (ROLLBACK if it throws), holding the mutex.
    template <class F> auto transaction(F&& fn) {
        std::lock_guard lock(mutex_);
        exec("BEGIN IMMEDIATE");
        try {
            if constexpr (std::is_void_v<decltype(fn(*this))>) {
                fn(*this);
                exec("COMMIT");
            } else {
                auto r = fn(*this);
                exec("COMMIT");
                return r;
            }
        } catch (...) {
            sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
            throw;
        }
    }

    Statement prepare(std::string_view sql) { return Statement(db_, sql); }
    // Runs the INSERT `sql` with `args` in a transaction of its own; the new row's id.
    template <class... A> std::int64_t insert(std::string_view sql, const A&... args) {
        return transaction([&](Database& db) {
            auto st = db.prepare(sql);
            st.bind_all(args...);
            st.run();
            return db.last_insert_id();
        });
    }
    // The row `sql` selects for `key` (its one parameter) as `read(Statement&)` makes it;
    // throws `missing` when there is none.
    template <class F> auto row(std::string_view sql, std::int64_t key, const NotFound& missing, F&& read) {
        return with([&](Database& db) {
            auto st = db.prepare(sql);
            st.bind_all(key);
            if (!st.step()) throw missing;
            return read(st);
        });
    }
    void exec(const std::string& sql);  // only for fixed SQL text (pragmas, migrations)
    std::int64_t last_insert_id() const { return sqlite3_last_insert_rowid(db_); }
    int changes() const { return sqlite3_changes(db_); }
    int schema_version();
    // Bytes [offset, offset + n) of the TEXT or BLOB `column` of row `rowid` of `table`
    // (fixed names from the code, never from a request), read in place (sqlite3_blob) so a
    // large value is never held whole; fewer bytes at its end, and the value's full size.
    // nullopt when the row is gone. The caller holds the connection (with()); a long value
    // is read in several calls, each under a short hold, so a writer never waits for a
    // slow reader.
    struct ValueRange {
        std::string bytes;
        std::size_t total = 0;
    };
    std::optional<ValueRange> read_range(const char* table, const char* column, std::int64_t rowid, std::size_t offset,
                                         std::size_t n);

private:
    void migrate(const std::filesystem::path& dir);
    sqlite3* db_ = nullptr;
    std::recursive_mutex mutex_;
};

// UTC timestamp, ISO 8601 with seconds ("2026-01-02T03:04:05Z").
std::string utc_now();

}  // namespace triax::service
