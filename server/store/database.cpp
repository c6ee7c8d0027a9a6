#include "server/store/database.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <sstream>

namespace triax::service {

namespace {
[[noreturn]] void fail(sqlite3* db, int rc, std::string_view what) {
    throw StoreError(std::string(what) + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)), rc);
}
}  // namespace

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db) {
    int rc = sqlite3_prepare_v2(db, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) fail(db, rc, "prepare");
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::bind(int index, const SqlValue& v) {
    int rc = SQLITE_OK;
    if (std::holds_alternative<std::nullptr_t>(v)) rc = sqlite3_bind_null(stmt_, index);
    else if (auto* i = std::get_if<std::int64_t>(&v)) rc = sqlite3_bind_int64(stmt_, index, *i);
    else if (auto* d = std::get_if<double>(&v)) rc = sqlite3_bind_double(stmt_, index, *d);
    else if (auto* b = std::get_if<Blob>(&v))
        rc = sqlite3_bind_blob(stmt_, index, b->bytes.data(), static_cast<int>(b->bytes.size()), SQLITE_TRANSIENT);
    else {
        const auto& s = std::get<std::string>(v);
        rc = sqlite3_bind_text(stmt_, index, s.data(), static_cast<int>(s.size()), SQLITE_TRANSIENT);
    }
    if (rc != SQLITE_OK) fail(db_, rc, "bind");
    return *this;
}

bool Statement::step() {
    int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db_, rc, "step");
}

void Statement::run() {
    while (step()) {
    }
}

std::int64_t Statement::int64(int col) const { return sqlite3_column_int64(stmt_, col); }
double Statement::real(int col) const { return sqlite3_column_double(stmt_, col); }
std::string Statement::blob(int col) const {
    const auto* p = static_cast<const char*>(sqlite3_column_blob(stmt_, col));
    return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col))) : std::string();
}
bool Statement::is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
std::string Statement::text(int col) const {
    const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, col));
    return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col))) : std::string();
}

Database::Database(const std::filesystem::path& file, const std::filesystem::path& migrations_dir) {
    int rc = sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                             nullptr);
    if (rc != SQLITE_OK) {
        std::string msg = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
        sqlite3_close(db_);
        db_ = nullptr;
        throw StoreError("cannot open database " + file.string() + ": " + msg, rc);
    }
    sqlite3_busy_timeout(db_, 5000);
    try {
        // WAL: readers never block the writer; synchronous=NORMAL in WAL keeps every
        // committed transaction across a process kill (only an OS crash may drop the last ones).
        exec("PRAGMA journal_mode=WAL");
        exec("PRAGMA synchronous=NORMAL");
        exec("PRAGMA foreign_keys=ON");
        migrate(migrations_dir);
    } catch (...) {
        sqlite3_close(db_);
        db_ = nullptr;
        throw;
    }
}

Database::~Database() { sqlite3_close(db_); }

void Database::exec(const std::string& sql) {
    char* err = nullptr;
    int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err);
    if (rc != SQLITE_OK) {
        std::string msg = err ? err : sqlite3_errstr(rc);
        sqlite3_free(err);
        throw StoreError(msg, rc);
    }
}

int Database::schema_version() {
    std::lock_guard lock(mutex_);
    auto st = prepare("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
    st.step();
    return static_cast<int>(st.int64(0));
}

void Database::migrate(const std::filesystem::path& dir) {
    exec("CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL, "
         "applied_at TEXT NOT NULL)");
    if (!std::filesystem::is_directory(dir))
        throw StoreError("migrations directory not found: " + dir.string(), SQLITE_CANTOPEN);
    // Files are NNN_description.sql; the number is the version, applied in ascending order.
    std::vector<std::pair<int, std::filesystem::path>> files;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".sql") continue;
        const auto stem = e.path().stem().string();
        const auto us = stem.find('_');
        try {
            files.emplace_back(std::stoi(stem.substr(0, us)), e.path());
        } catch (const std::exception&) {
            throw StoreError("migration file name must start with a number: " + e.path().string(), SQLITE_ERROR);
        }
    }
    std::sort(files.begin(), files.end());
    for (const auto& [version, path] : files) {
        auto q = prepare("SELECT 1 FROM schema_migrations WHERE version = ?");
        q.bind_all(version);
        if (q.step()) continue;
        std::ifstream in(path);
        std::stringstream sql;
        sql << in.rdbuf();
        exec("BEGIN IMMEDIATE");
        try {
            exec(sql.str());
            auto ins = prepare("INSERT INTO schema_migrations(version, name, applied_at) VALUES (?, ?, ?)");
            ins.bind_all(version, path.filename().string(), utc_now());
            ins.run();
            exec("COMMIT");
        } catch (const StoreError& e) {
            sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
            throw StoreError("migration " + path.filename().string() + " failed: " + e.what(), e.code);
        }
    }
}

std::string utc_now() {
    const auto t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

std::optional<Database::ValueRange> Database::read_range(const char* table, const char* column, std::int64_t rowid,
                                                std::size_t offset, std::size_t n) {
    sqlite3_blob* blob = nullptr;
    const int rc = sqlite3_blob_open(db_, "main", table, column, rowid, 0, &blob);
    if (rc != SQLITE_OK) {
        sqlite3_blob_close(blob);  // a no-op on nullptr
        if (rc == SQLITE_ERROR) return std::nullopt;  // no such row (or the value is not text/blob)
        throw StoreError(std::string("cannot read ") + table + "." + column + ": " + sqlite3_errmsg(db_), rc);
    }
    ValueRange out;
    out.total = static_cast<std::size_t>(sqlite3_blob_bytes(blob));
    if (offset < out.total && n > 0) {
        out.bytes.resize(std::min(n, out.total - offset));
        const int read =
            sqlite3_blob_read(blob, out.bytes.data(), static_cast<int>(out.bytes.size()), static_cast<int>(offset));
        if (read != SQLITE_OK) {
            sqlite3_blob_close(blob);
            throw StoreError(std::string("cannot read ") + table + "." + column, read);
        }
    }
    sqlite3_blob_close(blob);
    return out;
}

}  // namespace triax::service
