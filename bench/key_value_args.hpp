#pragma once
// key=value command-line overrides of a bench program's defaults: an unknown key or an
// argument without '=' is refused with the list of keys (exit code 2 for the caller).
#include <cstdio>
#include <map>
#include <string>

namespace triax::bench {

// Applies argv[1..] to `kv` (whose keys are the accepted ones). Returns false after
// printing the refusal on stderr.
inline bool read_key_values(int argc, char** argv, std::map<std::string, std::string>& kv) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto eq = a.find('=');
        if (eq == std::string::npos || !kv.count(a.substr(0, eq))) {
            std::fprintf(stderr, "unknown argument '%s' (key=value; keys:", a.c_str());
            for (const auto& [k, v] : kv) std::fprintf(stderr, " %s", k.c_str());
            std::fprintf(stderr, ")\n");
            return false;
        }
        kv[a.substr(0, eq)] = a.substr(eq + 1);
    }
    return true;
}

}  // namespace triax::bench
