// Built instead of the gl tests when CMake found no OSMesa: one test that skips, saying why, so
// the missing backend shows in the test report rather than as silent green.
#include <gtest/gtest.h>

TEST(Gl, Unavailable) {
  GTEST_SKIP() << "the gl backend is not built: OSMesa was not found at configure time "
                  "(install libosmesa6-dev, e.g. with ./setup.sh, and configure again)";
}
