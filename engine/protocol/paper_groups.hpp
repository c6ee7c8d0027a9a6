#pragma once
// The paper's test groups (Table 2) as named presets: A (50 kPa), B (100 kPa), C (200 kPa)
// at w = 8.9 %, D (10.2 %) and E (12.1 %) at 100 kPa. D and E differ from B only through
// the moisture content (which acts on bond strength).
#include <string>
#include <vector>

#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

struct PaperGroup {
    std::string name;         // "A".."E"
    std::string description;
    TestScheme scheme;
};

std::vector<PaperGroup> paper_groups();
// Throws InputError listing the valid names when `name` is unknown.
TestScheme paper_group(const std::string& name);

}  // namespace triax::protocol
