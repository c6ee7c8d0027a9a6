#include "server/io/bounded_json.hpp"

#include <unordered_set>
#include <vector>

namespace triax::io {

using nlohmann::json;

std::string json_pointer_token(std::string_view key) {
    std::string out;
    out.reserve(key.size());
    for (char c : key) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

namespace {

// Where the parser stands: one frame per open container.
struct Frame {
    bool object = false;
    std::string key;                       // object: the member being read
    std::size_t members = 0;               // members completed so far
    std::unordered_set<std::string> keys;  // object: keys seen
};

class Walker {
public:
    explicit Walker(const JsonLimits& l) : limits_(l) {}

    bool on(int depth, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
            case json::parse_event_t::array_start:
                if (depth + 1 > limits_.max_depth)
                    fail("nesting deeper than " + std::to_string(limits_.max_depth) + " levels");
                frames_.push_back(Frame{event == json::parse_event_t::object_start, {}, 0, {}});
                break;
            case json::parse_event_t::key: {
                Frame& f = frames_.back();
                const auto& k = parsed.get_ref<const std::string&>();
                f.key = k;
                if (k.size() > limits_.max_string_bytes)
                    fail("key longer than " + std::to_string(limits_.max_string_bytes) + " bytes");
                if (!f.keys.insert(k).second) fail("duplicate key");
                break;
            }
            case json::parse_event_t::value:
                if (parsed.is_string() && parsed.get_ref<const std::string&>().size() > limits_.max_string_bytes)
                    fail("string longer than " + std::to_string(limits_.max_string_bytes) + " bytes");
                member_done();
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                frames_.pop_back();
                member_done();
                break;
        }
        return true;
    }

private:
    void member_done() {
        if (frames_.empty()) return;
        Frame& f = frames_.back();
        if (f.members + 1 > limits_.max_elements)  // pointer: the member that is one too many
            fail(std::string(f.object ? "object" : "array") + " with more than " +
                 std::to_string(limits_.max_elements) + " members");
        ++f.members;
    }

public:
    // Pointer of the value being read: the path of open containers and their current member.
    std::string pointer() const {
        std::string p;
        for (const auto& f : frames_) p += "/" + (f.object ? json_pointer_token(f.key) : std::to_string(f.members));
        return p;
    }

private:
    [[noreturn]] void fail(const std::string& why) const { throw JsonLimitError(why, pointer(), 0, false); }

    const JsonLimits& limits_;
    std::vector<Frame> frames_;
};

}  // namespace

json parse_bounded_json(std::string_view text, const JsonLimits& limits) {
    Walker walker(limits);
    try {
        return json::parse(text.begin(), text.end(),
                           [&walker](int depth, json::parse_event_t event, json& parsed) {
                               return walker.on(depth, event, parsed);
                           });
    } catch (const json::parse_error& e) {
        throw JsonLimitError(std::string("not valid JSON (byte ") + std::to_string(e.byte) + "): " + e.what(), "",
                             e.byte, true);
    } catch (const json::out_of_range&) {
        // Well-formed JSON whose number is beyond a double (1e400): a bad value, named by
        // where the parser stood (the callback has seen its key, not the value).
        throw JsonLimitError("a number beyond the range of a double (about 1.8e308)", walker.pointer(), 0, false);
    } catch (const json::exception&) {
        throw JsonLimitError("not usable JSON", walker.pointer(), 0, true);
    }
}

}  // namespace triax::io
