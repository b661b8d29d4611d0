/**
 * @file ptvTestCheck.h
 * @brief Shared by the C++ tests: Check(condition, what) reports and counts failures (passing
 *        checks stay silent: their text may quote an observed VTK error, which ctest rejects);
 *        TempDir() is the -T folder (or $PTV_TEST_TEMP).
 *
 * Everything is in an anonymous namespace: each test translation unit has its own counter.
 */
#ifndef ptvTestCheck_h
#define ptvTestCheck_h

#include "vtkTestUtilities.h"
#include "vtksys/SystemTools.hxx"

#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
int failures = 0;

void Check(bool ok, const std::string& what)
{
  if (!ok)
  {
    std::cerr << "FAILED: " << what << "\n";
    ++failures;
  }
}

/// EXIT_SUCCESS when no Check failed.
int TestResult()
{
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

std::string TempDir(int argc, char* argv[])
{
  char* dir = vtkTestUtilities::GetArgOrEnvOrDefault("-T", argc, argv, "PTV_TEST_TEMP", ".");
  std::string result = dir;
  delete[] dir;
  vtksys::SystemTools::MakeDirectory(result);
  return result;
}
}

#endif
