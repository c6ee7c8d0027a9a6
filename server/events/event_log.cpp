#include "server/events/event_log.hpp"

namespace triax::service {

bool is_terminal_event(const std::string& type) { return type == "done" || type == "error"; }

EventLog::EventLog(Database& db, std::string table, std::string owner)
    : db_(db),
      insert_sql_("INSERT INTO " + table + "(" + owner + ", seq, type, data) VALUES (?, ?, ?, ?)"),
      select_sql_("SELECT seq, type, data FROM " + table + " WHERE " + owner + " = ? AND seq > ? ORDER BY seq LIMIT ?"),
      max_sql_("SELECT COALESCE(MAX(seq), 0) FROM " + table + " WHERE " + owner + " = ?"),
      last_type_sql_("SELECT type FROM " + table + " WHERE " + owner + " = ? ORDER BY seq DESC LIMIT 1"),
      delete_sql_("DELETE FROM " + table + " WHERE " + owner + " = ?") {}

bool EventLog::ended(std::int64_t owner) const {
    return db_.with([&](Database& db) {
        auto st = db.prepare(last_type_sql_);
        st.bind_all(owner);
        return st.step() && is_terminal_event(st.text(0));
    });
}

std::int64_t EventLog::last_seq_locked(Database& db, std::int64_t owner) {
    auto it = last_seq_.find(owner);
    if (it != last_seq_.end()) return it->second;
    auto st = db.prepare(max_sql_);
    st.bind_all(owner);
    st.step();
    return last_seq_[owner] = st.int64(0);
}

std::int64_t EventLog::append_in(Database& tx, std::int64_t owner, const std::string& type, const nlohmann::json& data) {
    std::lock_guard lock(mutex_);
    const auto seq = last_seq_locked(tx, owner) + 1;
    auto st = tx.prepare(insert_sql_);
    st.bind_all(owner, seq, type, data.dump());
    st.run();
    last_seq_[owner] = seq;
    return seq;
}

std::int64_t EventLog::append(std::int64_t owner, const std::string& type, const nlohmann::json& data) {
    const auto seq = db_.with([&](Database& db) { return append_in(db, owner, type, data); });
    notify();
    return seq;
}

void EventLog::notify() { cv_.notify_all(); }

void EventLog::forget_in(Database& tx, std::int64_t owner) {
    std::lock_guard lock(mutex_);
    auto st = tx.prepare(delete_sql_);
    st.bind_all(owner);
    st.run();
    last_seq_.erase(owner);  // the id may be given again
}

std::vector<StoredEvent> EventLog::since(std::int64_t owner, std::int64_t after_seq, int limit) const {
    return db_.with([&](Database& db) {
        std::vector<StoredEvent> out;
        auto st = db.prepare(select_sql_);
        st.bind_all(owner, after_seq, limit);
        while (st.step()) out.push_back({st.int64(0), st.text(1), st.text(2)});
        return out;
    });
}

void EventLog::wait(std::int64_t owner, std::int64_t after_seq, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, timeout, [&] {
        if (stopping_) return true;
        auto it = last_seq_.find(owner);
        return it != last_seq_.end() && it->second > after_seq;
    });
}

void EventLog::shutdown() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    cv_.notify_all();
}

bool EventLog::stopping() const {
    std::lock_guard lock(mutex_);
    return stopping_;
}

}  // namespace triax::service
