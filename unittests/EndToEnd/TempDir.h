//===- TempDir.h - A test's own temporary directory -----------------------===//
//
// ctest runs each test as its own process, two at a time, so a fixed path
// under /tmp is shared by tests running at once: one test read a file while
// another rewrote it. Tests put their files in a fresh directory instead,
// removed with everything in it when the test is done.
//
//===----------------------------------------------------------------------===//
#ifndef OSL_UNITTESTS_TEMPDIR_H
#define OSL_UNITTESTS_TEMPDIR_H

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <stdlib.h>

namespace osl::test {

/// A fresh directory under gtest's temporary directory; `path` is empty if
/// it could not be made.
class TempDir {
public:
  explicit TempDir(const std::string &prefix) {
    std::string pattern = ::testing::TempDir() + prefix + "-XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back(0);
    path = mkdtemp(buffer.data()) ? std::string(buffer.data()) : "";
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path.empty())
      std::filesystem::remove_all(path, ignored);
  }
  TempDir(const TempDir &) = delete;
  TempDir &operator=(const TempDir &) = delete;
  std::string path;
};

} // namespace osl::test

#endif // OSL_UNITTESTS_TEMPDIR_H
