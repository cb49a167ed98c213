// `semap --version` names the allocator: with SEMAP_MIMALLOC, mimalloc must really serve malloc.
#include <gtest/gtest.h>

#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

TEST(SemapAllocator, VersionNamesTheAllocatorServingMalloc) {
  const test::CliRun r = test::RunSemap("--version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("semap 0.1.0 (")) << r.output;
#ifdef SEMAP_EXPECT_MIMALLOC
  EXPECT_TRUE(r.Has("(mimalloc 2.")) << r.output;
  EXPECT_FALSE(r.Has("not serving malloc")) << r.output;
  EXPECT_TRUE(r.Has(", decommit delay 1000 ms)")) << r.output;
#else
  EXPECT_TRUE(r.Has("(system malloc)")) << r.output;
#endif
}

#ifdef SEMAP_EXPECT_MIMALLOC
// Freed memory stays committed for a second (tools/allocator.h), unless the user's environment says
// otherwise.
TEST(SemapAllocator, TheDecommitDelayIsASecondUnlessTheEnvironmentSetsIt) {
  const test::CliRun r =
      test::RunShell("MIMALLOC_DECOMMIT_DELAY=25 " + std::string(SEMAP_EXE) + " --version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has(", decommit delay 25 ms)")) << r.output;
}
#endif

}  // namespace
}  // namespace semap::tools
