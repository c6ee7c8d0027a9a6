#pragma once
// The persisted, ordered event log of one kind of job (runs or diagnoses). Every event is
// written to SQLite before any client sees it, with a per-job sequence number that is the
// SSE `id:`; a reconnecting client (Last-Event-ID) or a late one reads the history from
// the table, so nothing depends on who was connected when the event happened.
// Waiters block on a condition variable with a timeout, never on the database.
#include "server/store/database.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace triax::service {

struct StoredEvent {
    std::int64_t seq = 0;
    std::string type;
    std::string data;  // JSON text
};

// Event types after which a stream ends.
bool is_terminal_event(const std::string& type);

class EventLog {
public:
    // table: "run_events" or "diagnosis_events"; owner_column: "run_id" or "diagnosis_id".
    // Both are fixed identifiers chosen by the code, never user input.
    EventLog(Database& db, std::string table, std::string owner_column);

    // Persists the event and wakes the waiters. Returns its sequence number.
    std::int64_t append(std::int64_t owner, const std::string& type, const nlohmann::json& data);
    // Same, inside a transaction the caller already holds (Database::transaction).
    std::int64_t append_in(Database& tx, std::int64_t owner, const std::string& type, const nlohmann::json& data);
    void notify();
    // Deletes the owner's events, inside the caller's transaction (a job whose submission
    // was refused).
    void forget_in(Database& tx, std::int64_t owner);

    // True when the owner's last event is terminal: nothing more will come.
    bool ended(std::int64_t owner) const;
    std::vector<StoredEvent> since(std::int64_t owner, std::int64_t after_seq, int limit) const;
    // Waits until an event newer than after_seq may exist, the timeout passes, or shutdown.
    void wait(std::int64_t owner, std::int64_t after_seq, std::chrono::milliseconds timeout);
    void shutdown();
    bool stopping() const;

private:
    std::int64_t last_seq_locked(Database& db, std::int64_t owner);
    Database& db_;
    std::string insert_sql_, select_sql_, max_sql_, last_type_sql_, delete_sql_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::map<std::int64_t, std::int64_t> last_seq_;  // cache of MAX(seq) per owner
    bool stopping_ = false;
};

}  // namespace triax::service
