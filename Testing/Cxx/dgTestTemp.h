// Temporary file names that no other test can use at the same time: ctest
// runs every gtest case as its own process, in parallel, and several builds
// (or clones) may test on one machine at once.
#ifndef dgTestTemp_h
#define dgTestTemp_h

#include <gtest/gtest.h>

#include <string>

namespace dgtest
{
// The build's own folder (DG_TEST_TMP_DIR, from the CMake) keeps builds and
// clones apart, the test's name keeps the cases apart; a rerun overwrites
// its own files instead of piling up new ones.
inline std::string TempPath(const std::string& name)
{
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
  for (char& c : test)
  {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    c = plain ? c : '_'; // parameterised names hold '/'
  }
#ifdef DG_TEST_TMP_DIR
  const std::string dir = DG_TEST_TMP_DIR;
#else
  const std::string dir = ::testing::TempDir();
#endif
  return dir + "dg_" + test + "_" + name;
}
} // namespace dgtest

#endif
