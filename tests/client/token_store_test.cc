// The client's token store: readable by its owner only (protocol.md, Security), whatever the
// umask, and it round-trips through its file.
#include "client/token_store.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "common/check.h"

namespace viscera::client {
namespace {

TEST(TokenStore, SavesMode0600AndReadsBack) {
  const std::string path = ::testing::TempDir() + "/viscera_token_store_test.json";
  std::remove(path.c_str());
  const mode_t old_mask = umask(022);  // a usual umask would give 0644
  {
    TokenStore store(path);
    store.Put(7, {{0xde, 0xad, 0xbe, 0xef}, "server-a"});
    store.Put(9, {{0x01}, "server-b"});
  }
  umask(old_mask);
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600);
  TokenStore again(path);
  ASSERT_NE(again.Find(7), nullptr);
  EXPECT_EQ(again.Find(7)->token, (std::vector<uint8_t>{0xde, 0xad, 0xbe, 0xef}));
  EXPECT_EQ(again.Find(7)->server_id, "server-a");
  again.Erase(9);
  EXPECT_EQ(TokenStore(path).Find(9), nullptr);
  EXPECT_NE(TokenStore(path).Find(7), nullptr);
  std::remove(path.c_str());
}

TEST(TokenStore, HexRoundTripsAndRefusesBadHex) {
  EXPECT_EQ(ToHex({0x00, 0x0f, 0xa5, 0xff}), "000fa5ff");
  EXPECT_EQ(FromHex("000fa5ff"), (std::vector<uint8_t>{0x00, 0x0f, 0xa5, 0xff}));
  EXPECT_THROW(FromHex("abc"), InputError);
  EXPECT_THROW(FromHex("zz"), InputError);
}

}  // namespace
}  // namespace viscera::client
