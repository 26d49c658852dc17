// An environment variable set for a scope and restored after it (to its earlier value, or unset),
// also when a REQUIRE in the scope throws: the renderer reads its CAUSTIC_* switches when it is
// made or loads a scene, and a switch left set by a failed test would change every later one.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace caustic::test {

class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        if (const char* was = std::getenv(name)) m_was = was;
        ::setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (m_was) ::setenv(m_name.c_str(), m_was->c_str(), 1);
        else ::unsetenv(m_name.c_str());
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string m_name;
    std::optional<std::string> m_was;
};

}  // namespace caustic::test
