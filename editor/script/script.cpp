#include "editor/script/script.h"

#include "editor/script/script_commands.h"

#include <charconv>
#include <cstdlib>

namespace caustic::editor {

bool parseFloat(const std::string& s, float* out) {
    if (s.empty()) return false;
    char* end = nullptr;
    const float v = std::strtof(s.c_str(), &end);
    if (end != s.c_str() + s.size()) return false;
    *out = v;
    return true;
}

bool parseInt(const std::string& s, int* out) {
    int v = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size()) return false;
    *out = v;
    return true;
}

ScriptParseResult parseScript(const std::string& text, const std::string& fileForMessages) {
    ScriptParseResult result;
    int lineNo = 0;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t eol = text.find('\n', pos);
        if (eol == std::string::npos) eol = text.size();
        std::string line = text.substr(pos, eol - pos);
        pos = eol + 1;
        ++lineNo;
        std::vector<std::string> words;
        std::string word;
        bool inQuotes = false, hasWord = false;
        for (size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (inQuotes) {
                if (c == '"') inQuotes = false;
                else word += c;
            } else if (c == '"') {
                inQuotes = true;
                hasWord = true;
            } else if (c == '#') {
                break;
            } else if (c == ' ' || c == '\t' || c == '\r') {
                if (hasWord) words.push_back(word);
                word.clear();
                hasWord = false;
            } else {
                word += c;
                hasWord = true;
            }
        }
        auto fail = [&](const std::string& why) {
            result.error = fileForMessages + ":" + std::to_string(lineNo) + ": " + why;
            result.lines.clear();
            return result;
        };
        if (inQuotes) return fail("unterminated quote");
        if (hasWord) words.push_back(word);
        if (words.empty()) continue;
        ScriptLine sl{lineNo, words[0], std::vector<std::string>(words.begin() + 1, words.end())};
        const ScriptCommand* sig = findScriptCommand(sl.op);
        if (!sig) return fail("unknown command '" + sl.op + "'");
        const int n = static_cast<int>(sl.args.size());
        if (n < sig->minArgs || n > sig->maxArgs)
            return fail(sl.op + ": expected " + std::to_string(sig->minArgs) +
                        (sig->maxArgs != sig->minArgs ? " to " + std::to_string(sig->maxArgs) : std::string()) +
                        " arguments, got " + std::to_string(n));
        for (int i = 0; i < static_cast<int>(sig->numeric.size()) && i < n; ++i) {
            float f = 0.0f;
            if (!parseFloat(sl.args[static_cast<size_t>(i)], &f))
                return fail(sl.op + ": argument " + std::to_string(i + 1) + ": expected a number, got '" +
                            sl.args[static_cast<size_t>(i)] + "'");
        }
        result.lines.push_back(std::move(sl));
    }
    return result;
}

}  // namespace caustic::editor
