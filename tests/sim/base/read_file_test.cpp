// base::read_file: the whole file under the limit, and which way it failed otherwise (the size
// checked before anything is read).
#include "base/read_file.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace cathbox::base {
namespace {

class ReadFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = ::testing::TempDir() + "cathbox-read-file-" + std::to_string(::getpid()) + ".bin";
    std::ofstream(path_, std::ios::binary) << std::string("ab\0\r\ncd", 7);
  }
  void TearDown() override { std::remove(path_.c_str()); }
  std::string path_;
};

TEST_F(ReadFile, GivesEveryByteUpToTheLimit) {
  const Result<std::string, ReadFileError> bytes = read_file(path_, 7);
  ASSERT_TRUE(bytes);
  EXPECT_EQ(*bytes, std::string("ab\0\r\ncd", 7));
}

TEST_F(ReadFile, AFileOverTheLimitIsTooLargeWithItsSize) {
  const Result<std::string, ReadFileError> bytes = read_file(path_, 6);
  ASSERT_FALSE(bytes);
  EXPECT_EQ(bytes.error().kind, ReadFileError::Kind::kTooLarge);
  EXPECT_EQ(bytes.error().size_bytes, 7u);
}

TEST_F(ReadFile, AMissingFileOrAFolderCannotBeOpened) {
  const Result<std::string, ReadFileError> missing = read_file(path_ + ".none", 100);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().kind, ReadFileError::Kind::kCannotOpen);
  const Result<std::string, ReadFileError> folder = read_file(::testing::TempDir(), 100);
  ASSERT_FALSE(folder);
  EXPECT_EQ(folder.error().kind, ReadFileError::Kind::kCannotOpen);
}

}  // namespace
}  // namespace cathbox::base
