// The test binaries that render set Mesa's environment as the corridorsim program's main() does:
// once, before the first test case and before any thread exists (render/software_rasterizer.h).
// Linked into every test binary that renders (tests/CMakeLists.txt).

#define CATCH_CONFIG_EXTERNAL_INTERFACES
#include <catch2/catch.hpp>

#include "render/software_rasterizer.h"

namespace {

class SoftwareRasterizerListener : public Catch::TestEventListenerBase {
 public:
  using TestEventListenerBase::TestEventListenerBase;
  void testRunStarting(const Catch::TestRunInfo& info) override {
    corridorsim::render::PinSoftwareRasterizer();
    TestEventListenerBase::testRunStarting(info);
  }
};

}  // namespace

CATCH_REGISTER_LISTENER(SoftwareRasterizerListener)
