// The one main() of caustic_editor_tests (the editor's model, tested without a window).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
