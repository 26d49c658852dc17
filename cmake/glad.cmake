# glad2 (PyPI glad2==2.0.8, in its own venv made by setup.sh) generates the OpenGL 4.5 core loader
# at build time. --reproducible: use the GL spec bundled in the package, never the network.
set(CAUSTIC_GLAD_PYTHON "${CAUSTIC_DEPS_DIR}/venv/bin/python" CACHE FILEPATH "Python with glad2 installed")
if(NOT EXISTS "${CAUSTIC_GLAD_PYTHON}")
  message(FATAL_ERROR "glad2 not found at ${CAUSTIC_GLAD_PYTHON}: run ./setup.sh (it creates the venv), "
                      "or pass -DCAUSTIC_GLAD_PYTHON=<python with glad2==2.0.8>")
endif()

set(_glad_out "${CMAKE_BINARY_DIR}/glad")
set(_glad_ext "GL_KHR_debug,GL_ARB_bindless_texture,GL_ARB_gpu_shader_int64")
add_custom_command(
  OUTPUT "${_glad_out}/src/gl.c" "${_glad_out}/include/glad/gl.h"
  COMMAND "${CAUSTIC_GLAD_PYTHON}" -m glad --quiet --reproducible --api gl:core=4.5
          --extensions ${_glad_ext} --out-path "${_glad_out}" c
  COMMENT "Generating the OpenGL 4.5 core loader with glad2"
  VERBATIM)
add_library(caustic_glad STATIC "${_glad_out}/src/gl.c")
target_include_directories(caustic_glad SYSTEM PUBLIC "${_glad_out}/include")
set_target_properties(caustic_glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
