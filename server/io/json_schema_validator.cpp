#include "server/io/json_schema_validator.hpp"

#include <cmath>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace triax::io {

using nlohmann::json;

std::string pointer_token(const std::string& name) {
    std::string out;
    for (char c : name) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

JsonSchemaValidator::JsonSchemaValidator(json schema) : schema_(std::move(schema)) {
    if (!schema_.is_object() && !schema_.is_boolean())
        throw std::invalid_argument("a JSON Schema must be an object or a boolean");
}

std::vector<SchemaViolation> JsonSchemaValidator::validate(const json& instance) const {
    std::vector<SchemaViolation> out;
    check(schema_, instance, "", out, 0);
    return out;
}

const json& JsonSchemaValidator::resolve(const std::string& ref) const {
    if (ref.empty() || ref[0] != '#') throw std::invalid_argument("only local $ref is supported: " + ref);
    try {
        return schema_.at(json::json_pointer(ref.substr(1)));
    } catch (const json::exception&) {
        throw std::invalid_argument("unresolvable $ref " + ref);
    }
}

namespace {

bool has_type(const json& v, const std::string& t) {
    if (t == "object") return v.is_object();
    if (t == "array") return v.is_array();
    if (t == "string") return v.is_string();
    if (t == "boolean") return v.is_boolean();
    if (t == "null") return v.is_null();
    if (t == "number") return v.is_number();
    if (t == "integer") {
        if (v.is_number_integer()) return true;
        if (v.is_number_float()) {
            const double d = v.get<double>();
            return std::isfinite(d) && d == std::floor(d);
        }
        return false;
    }
    return false;
}

std::string short_dump(const json& v) {
    auto s = v.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string number_text(double d) {
    std::ostringstream os;
    os << d;
    return os.str();
}

}  // namespace

void JsonSchemaValidator::check(const json& s, const json& v, const std::string& ptr, std::vector<SchemaViolation>& out,
                                int depth) const {
    if (depth > 64) throw std::invalid_argument("JSON Schema nests $ref too deeply (a cycle?)");
    if (s.is_boolean()) {
        if (!s.get<bool>()) out.push_back({ptr, "no value is allowed here"});
        return;
    }
    if (auto it = s.find("$ref"); it != s.end()) {
        check(resolve(it->get<std::string>()), v, ptr, out, depth + 1);
    }
    const auto where = ptr.empty() ? std::string("the document") : ptr;

    if (auto it = s.find("type"); it != s.end()) {
        bool ok = false;
        std::string names;
        if (it->is_string()) {
            ok = has_type(v, it->get<std::string>());
            names = it->get<std::string>();
        } else {
            for (const auto& t : *it) {
                ok = ok || has_type(v, t.get<std::string>());
                names += (names.empty() ? "" : " or ") + t.get<std::string>();
            }
        }
        if (!ok) {
            out.push_back({ptr, where + " must be of type " + names + ", got " + short_dump(v)});
            return;
        }
    }
    if (auto it = s.find("enum"); it != s.end()) {
        bool found = false;
        for (const auto& e : *it) found = found || e == v;
        if (!found) out.push_back({ptr, where + " must be one of " + short_dump(*it) + ", got " + short_dump(v)});
    }
    if (auto it = s.find("const"); it != s.end() && *it != v)
        out.push_back({ptr, where + " must equal " + short_dump(*it)});

    if (v.is_number()) {
        const double d = v.get<double>();
        if (!std::isfinite(d)) out.push_back({ptr, where + " must be a finite number"});
        const bool excl_min_flag = s.value("exclusiveMinimum", json()).is_boolean() && s["exclusiveMinimum"].get<bool>();
        const bool excl_max_flag = s.value("exclusiveMaximum", json()).is_boolean() && s["exclusiveMaximum"].get<bool>();
        if (auto it = s.find("minimum"); it != s.end()) {
            const double m = it->get<double>();
            if (excl_min_flag ? !(d > m) : !(d >= m))
                out.push_back({ptr, where + " = " + short_dump(v) + " must be " + (excl_min_flag ? "> " : ">= ") +
                                        number_text(m)});
        }
        if (auto it = s.find("maximum"); it != s.end()) {
            const double m = it->get<double>();
            if (excl_max_flag ? !(d < m) : !(d <= m))
                out.push_back({ptr, where + " = " + short_dump(v) + " must be " + (excl_max_flag ? "< " : "<= ") +
                                        number_text(m)});
        }
        if (auto it = s.find("exclusiveMinimum"); it != s.end() && it->is_number() && !(d > it->get<double>()))
            out.push_back({ptr, where + " = " + short_dump(v) + " must be > " + number_text(it->get<double>())});
        if (auto it = s.find("exclusiveMaximum"); it != s.end() && it->is_number() && !(d < it->get<double>()))
            out.push_back({ptr, where + " = " + short_dump(v) + " must be < " + number_text(it->get<double>())});
    }
    if (v.is_string()) {
        const auto& str = v.get_ref<const std::string&>();
        if (auto it = s.find("minLength"); it != s.end() && str.size() < it->get<std::size_t>())
            out.push_back({ptr, where + " must have at least " + it->dump() + " characters"});
        if (auto it = s.find("maxLength"); it != s.end() && str.size() > it->get<std::size_t>())
            out.push_back({ptr, where + " must have at most " + it->dump() + " characters"});
        if (auto it = s.find("pattern"); it != s.end() && !std::regex_search(str, std::regex(it->get<std::string>())))
            out.push_back({ptr, where + " must match the pattern " + it->get<std::string>()});
    }
    if (v.is_array()) {
        if (auto it = s.find("minItems"); it != s.end() && v.size() < it->get<std::size_t>())
            out.push_back({ptr, where + " must have at least " + it->dump() + " items, got " + std::to_string(v.size())});
        if (auto it = s.find("maxItems"); it != s.end() && v.size() > it->get<std::size_t>())
            out.push_back({ptr, where + " must have at most " + it->dump() + " items, got " + std::to_string(v.size())});
        if (auto it = s.find("items"); it != s.end()) {
            if (it->is_array()) {  // tuple form (draft 4-7)
                for (std::size_t i = 0; i < v.size() && i < it->size(); ++i)
                    check((*it)[i], v[i], ptr + "/" + std::to_string(i), out, depth + 1);
            } else {
                for (std::size_t i = 0; i < v.size(); ++i) check(*it, v[i], ptr + "/" + std::to_string(i), out, depth + 1);
            }
        }
    }
    if (v.is_object()) {
        if (auto it = s.find("required"); it != s.end())
            for (const auto& name : *it)
                if (!v.contains(name.get<std::string>()))
                    out.push_back({ptr + "/" + pointer_token(name.get<std::string>()),
                                   "required field '" + name.get<std::string>() + "' is missing"});
        const json* props = s.contains("properties") ? &s["properties"] : nullptr;
        for (const auto& [name, child] : v.items()) {
            const auto child_ptr = ptr + "/" + pointer_token(name);
            if (props && props->contains(name)) {
                check((*props)[name], child, child_ptr, out, depth + 1);
            } else if (auto ap = s.find("additionalProperties"); ap != s.end()) {
                if (ap->is_boolean() && !ap->get<bool>())
                    out.push_back({child_ptr, "unknown field '" + name + "'"});
                else if (ap->is_object())
                    check(*ap, child, child_ptr, out, depth + 1);
            }
        }
    }
    if (auto it = s.find("allOf"); it != s.end())
        for (const auto& sub : *it) check(sub, v, ptr, out, depth + 1);
    if (auto it = s.find("anyOf"); it != s.end()) {
        std::vector<SchemaViolation> best;
        bool ok = false;
        for (const auto& sub : *it) {
            std::vector<SchemaViolation> tmp;
            check(sub, v, ptr, tmp, depth + 1);
            if (tmp.empty()) { ok = true; break; }
            if (best.empty() || tmp.size() < best.size()) best = std::move(tmp);
        }
        // Report the closest alternative's errors: more useful than "matches none".
        if (!ok) out.insert(out.end(), best.begin(), best.end());
    }
    if (auto it = s.find("oneOf"); it != s.end()) {
        std::vector<SchemaViolation> best;
        int matches = 0;
        for (const auto& sub : *it) {
            std::vector<SchemaViolation> tmp;
            check(sub, v, ptr, tmp, depth + 1);
            if (tmp.empty()) ++matches;
            else if (best.empty() || tmp.size() < best.size()) best = std::move(tmp);
        }
        if (matches == 0) out.insert(out.end(), best.begin(), best.end());
        else if (matches > 1) out.push_back({ptr, where + " matches more than one alternative of oneOf"});
    }
    if (auto it = s.find("not"); it != s.end()) {
        std::vector<SchemaViolation> tmp;
        check(*it, v, ptr, tmp, depth + 1);
        if (tmp.empty()) out.push_back({ptr, where + " must not match the excluded form"});
    }
}

}  // namespace triax::io
