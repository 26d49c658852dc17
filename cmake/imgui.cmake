# Dear ImGui (docking branch) and ImGuizmo for the editor, built as static libraries from the files
# setup.sh extracts from the PyPI sdist imgui-bundle==1.93.0 into .deps/imgui (see
# docs/dependencies.md: the hello_imgui copy of ImGui is plain upstream docking).
# Third-party code: compiled without our warning flags, included as SYSTEM headers.
set(CAUSTIC_IMGUI_DIR "${CAUSTIC_DEPS_DIR}/imgui" CACHE PATH "Extracted Dear ImGui + ImGuizmo (setup.sh)")
if(NOT EXISTS "${CAUSTIC_IMGUI_DIR}/imgui/imgui.cpp" OR NOT EXISTS "${CAUSTIC_IMGUI_DIR}/imguizmo/ImGuizmo.cpp")
  message(FATAL_ERROR "Dear ImGui not found in ${CAUSTIC_IMGUI_DIR}: run ./setup.sh (it downloads "
                      "imgui-bundle 1.93.0 and extracts it), or pass -DCAUSTIC_IMGUI_DIR=<folder>")
endif()
find_package(glfw3 3.3 REQUIRED)

set(_im "${CAUSTIC_IMGUI_DIR}/imgui")
# The core (no backend): usable headless, e.g. by tests (set ImGuiBackendFlags_RendererHasTextures).
add_library(caustic_imgui STATIC
  "${_im}/imgui.cpp" "${_im}/imgui_draw.cpp" "${_im}/imgui_tables.cpp" "${_im}/imgui_widgets.cpp"
  "${_im}/imgui_demo.cpp" "${CAUSTIC_IMGUI_DIR}/imguizmo/ImGuizmo.cpp")
target_include_directories(caustic_imgui SYSTEM PUBLIC "${_im}" "${CAUSTIC_IMGUI_DIR}/imguizmo")
target_compile_options(caustic_imgui PRIVATE -w)

# The GLFW + OpenGL 3 backends (the OpenGL backend brings its own small loader).
add_library(caustic_imgui_backend STATIC
  "${_im}/backends/imgui_impl_glfw.cpp" "${_im}/backends/imgui_impl_opengl3.cpp")
target_include_directories(caustic_imgui_backend SYSTEM PUBLIC "${_im}/backends")
target_link_libraries(caustic_imgui_backend PUBLIC caustic_imgui glfw OpenGL::GL)
target_compile_options(caustic_imgui_backend PRIVATE -w)
