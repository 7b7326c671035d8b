// Diagnostics shared by every generator stage: a source position and an error that
// carries one, printed as `file:line:column: error: message` (the GCC convention, so
// editors and CI logs can jump to the place).
#pragma once

#include <stdexcept>
#include <initializer_list>
#include <string>
#include <vector>

namespace eomc {

struct SourcePos {
    std::string file;  // empty when the input did not come from a file
    int line = 0;      // 1-based; 0 when unknown
    int column = 0;    // 1-based; 0 when unknown

    bool known() const { return line > 0; }
    // The same file and line, `offset` characters further right (used to point inside
    // an expression string at the offending identifier).
    SourcePos shifted(int offset) const {
        SourcePos p = *this;
        if (p.column > 0) p.column += offset;
        return p;
    }
};

// "file:line:column" (or the parts of it that are known).
std::string to_string(const SourcePos& pos);

// Bad input: a scene that cannot be turned into a model. Exit code 2 in the CLI.
class InputError : public std::runtime_error {
public:
    InputError(SourcePos pos, const std::string& message);
    const SourcePos& where() const { return pos_; }
    const std::string& message() const { return message_; }

private:
    SourcePos pos_;
    std::string message_;
};

// "file:line:column: error: message"
std::string format_diagnostic(const SourcePos& pos, const std::string& message);

// Input that is accepted but probably not what was meant (printed, exit code unchanged).
struct Warning {
    SourcePos pos;
    std::string message;
};
// "file:line:column: warning: message"
std::string format_warning(const Warning& w);

// Closest candidate by edit distance, or "" when nothing is close enough to suggest.
std::string nearest_name(const std::string& word, const std::initializer_list<const char*>& candidates);
std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace eomc
