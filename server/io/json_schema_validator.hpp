#pragma once
// A small JSON Schema validator for the keywords our schemas use (Debian ships no
// validator library): type, properties, required, additionalProperties, minimum, maximum,
// exclusiveMinimum/Maximum (number form of draft 6+, boolean form of draft 4), enum, const,
// items, minItems, maxItems, minLength, maxLength, pattern, oneOf, anyOf, allOf, not, and
// local $ref ("#/definitions/x", "#/$defs/x"). Unknown keywords (title, description,
// default, examples, $schema, $id, format) are annotations and ignored. Every error names
// the JSON pointer of the offending value.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace triax::io {

struct SchemaViolation {
    std::string pointer;  // JSON pointer into the validated document ("" = the root)
    std::string message;
};

class JsonSchemaValidator {
public:
    explicit JsonSchemaValidator(nlohmann::json schema);
    // All violations found (empty = valid). Stops descending into a value after its own
    // type mismatch, so one mistake gives one message.
    std::vector<SchemaViolation> validate(const nlohmann::json& instance) const;
    const nlohmann::json& schema() const { return schema_; }

private:
    void check(const nlohmann::json& schema, const nlohmann::json& value, const std::string& pointer,
               std::vector<SchemaViolation>& out, int depth) const;
    const nlohmann::json& resolve(const std::string& ref) const;
    nlohmann::json schema_;
};

// Escapes a member name for use in a JSON pointer (RFC 6901: ~ -> ~0, / -> ~1).
std::string pointer_token(const std::string& name);

}  // namespace triax::io
