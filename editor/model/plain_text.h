// The schema's and the docs' short Markdown as plain text for tooltips: `code` loses its
// backticks, **bold** and *emphasis* their stars, [text](link) keeps its text (ImGui draws
// neither).
#pragma once

#include <string>
#include <string_view>

namespace caustic::editor {

std::string plainText(std::string_view markdown);

}  // namespace caustic::editor
