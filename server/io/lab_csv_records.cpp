#include "server/io/lab_format.hpp"

namespace triax::io {

// RFC 4180-style splitting with quoted fields ("" escapes a quote). Blank lines are
// dropped; line numbers refer to the uploaded text so errors point at what the user sees.
std::vector<CsvRecord> read_csv_records(std::string_view text, char sep) {
    std::vector<CsvRecord> out;
    int line = 1;
    std::size_t i = 0;
    if (text.substr(0, 3) == "\xEF\xBB\xBF") i = 3;  // UTF-8 byte-order mark from spreadsheet exports
    while (i < text.size()) {
        CsvRecord rec;
        rec.line = line;
        std::string field;
        int col = 1, field_col = 1;
        bool in_quotes = false, quoted = false;
        const int start_line = line;
        for (; i < text.size(); ++i) {
            const char c = text[i];
            if (in_quotes) {
                if (c == '"') {
                    if (i + 1 < text.size() && text[i + 1] == '"') { field += '"'; ++i; ++col; }
                    else in_quotes = false;
                } else {
                    if (c == '\n') { ++line; col = 0; }
                    field += c;
                }
                ++col;
                continue;
            }
            if (c == '"' && field.find_first_not_of(" \t") == std::string::npos) {
                in_quotes = quoted = true;
                field.clear();
                ++col;
                continue;
            }
            if (c == sep) {
                rec.fields.push_back(std::move(field));
                rec.columns.push_back(field_col);
                field.clear();
                quoted = false;
                ++col;
                field_col = col;
                continue;
            }
            if (c == '\r') continue;
            if (c == '\n') { ++i; ++line; break; }
            field += c;
            ++col;
        }
        if (in_quotes) throw LabParseError("unterminated quoted field", start_line, field_col);
        (void)quoted;
        rec.fields.push_back(std::move(field));
        rec.columns.push_back(field_col);
        bool blank = true;
        for (auto& f : rec.fields) {
            const auto a = f.find_first_not_of(" \t");
            const auto b = f.find_last_not_of(" \t");
            f = a == std::string::npos ? std::string() : f.substr(a, b - a + 1);
            blank = blank && f.empty();
        }
        if (!blank) out.push_back(std::move(rec));
    }
    return out;
}

}  // namespace triax::io
