// The hasher adds values in order: its digest is XXH3-64 of the concatenated bytes, whatever
// the pieces' sizes.
#include "base/xxh_hasher.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace cathbox::base {
namespace {

TEST(XxhHasher, DigestIsXxh3OfTheConcatenatedBytes) {
  const std::uint32_t a = 0xDEADBEEF;
  const double b = 2.5;
  const std::vector<float> c = {1.0f, -2.0f, 3.5f};
  XxhHasher h;
  h.add(a);
  h.add(b);
  h.add_all(c);
  std::vector<unsigned char> bytes(sizeof a + sizeof b + 8 + c.size() * sizeof(float));
  unsigned char* p = bytes.data();
  std::memcpy(p, &a, sizeof a);
  std::memcpy(p += sizeof a, &b, sizeof b);
  const std::uint64_t n = c.size();
  std::memcpy(p += sizeof b, &n, 8);
  std::memcpy(p + 8, c.data(), c.size() * sizeof(float));
  EXPECT_EQ(h.digest(), XXH3_64bits(bytes.data(), bytes.size()));
}

TEST(XxhHasher, EmptyIsTheEmptyInputsHash) {
  XxhHasher h;
  h.add_bytes(nullptr, 0);
  EXPECT_EQ(h.digest(), XXH3_64bits(nullptr, 0));
  EXPECT_EQ(h.digest(), 0x2D06800538D394C2ull);  // XXH3-64 of no bytes, seed 0 (xxHash's tests)
}

}  // namespace
}  // namespace cathbox::base
