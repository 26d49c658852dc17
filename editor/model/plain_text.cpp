#include "editor/model/plain_text.h"

namespace caustic::editor {

std::string plainText(std::string_view md) {
    std::string out;
    out.reserve(md.size());
    for (std::size_t i = 0; i < md.size(); ++i) {
        const char c = md[i];
        if (c == '`') continue;
        // Stars of emphasis: a run of one or two next to a word character (a lone "*" in "a * b"
        // or "2*pi" is kept: it has spaces or is inside a formula).
        if (c == '*') {
            const std::size_t run = md.substr(i).find_first_not_of('*');
            const std::size_t n = run == std::string_view::npos ? md.size() - i : run;
            const bool opens = i + n < md.size() && md[i + n] != ' ' && (i == 0 || md[i - 1] == ' ' || md[i - 1] == '(');
            const bool closes = i > 0 && md[i - 1] != ' ' && (i + n == md.size() || md[i + n] == ' ' || md[i + n] == '.' ||
                                                            md[i + n] == ',' || md[i + n] == ')' || md[i + n] == ':' || md[i + n] == ';');
            if (n <= 2 && (opens || closes)) {
                i += n - 1;
                continue;
            }
        }
        // [text](target) -> text
        if (c == '[') {
            const std::size_t close = md.find(']', i);
            if (close != std::string_view::npos && close + 1 < md.size() && md[close + 1] == '(') {
                const std::size_t end = md.find(')', close);
                if (end != std::string_view::npos) {
                    out += plainText(md.substr(i + 1, close - i - 1));
                    i = end;
                    continue;
                }
            }
        }
        out += c;
    }
    return out;
}

}  // namespace caustic::editor
