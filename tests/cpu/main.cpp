// The one main() of caustic_cpu_tests; every other tests/cpu/*.cpp file only adds test cases.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
