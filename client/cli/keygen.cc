// viscera keygen: writes a new pre-shared key file.
#include <cstdio>

#include "client/cli/commands.h"

namespace viscera::client::cli {

namespace {

std::string keygen_path;

}  // namespace

void SetUpKeygen(CLI::App* cmd, Common* common) {
  (void)common;
  cmd->add_option("file", keygen_path, "Key file to write")->required();
}

int RunKeygen(const std::string& url, const Common& c) {
  (void)url;
  (void)c;
  bus::MessageAuth::WriteKeyFile(keygen_path);
  std::printf("wrote a new key to %s\n", keygen_path.c_str());
  return 0;
}

}  // namespace viscera::client::cli
