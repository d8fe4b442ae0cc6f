#include "client/http_request.h"

#include <gtest/gtest.h>

namespace viscera::client {
namespace {

TEST(HttpRequest, FindsTheEndOfTheHead) {
  EXPECT_EQ(FindHeadEnd("GET / HTTP/1.1\r\nHost: x\r\n"), 0u);
  EXPECT_EQ(FindHeadEnd("GET / HTTP/1.1\r\n\r\nbody"), 18u);
  EXPECT_EQ(FindHeadEnd("GET / HTTP/1.0\n\n"), 16u);
}

TEST(HttpRequest, ParsesTheRequestLineAndFields) {
  HttpRequest request;
  ASSERT_EQ(ParseHttpRequest("GET /stream.mjpg?t=3 HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"
                             "Accept:  image/*  \r\n\r\n",
                             &request),
            "");
  EXPECT_EQ(request.method, "GET");
  EXPECT_EQ(request.target, "/stream.mjpg?t=3");
  EXPECT_EQ(request.path, "/stream.mjpg");
  EXPECT_EQ(request.version, "HTTP/1.1");
  ASSERT_EQ(request.fields.size(), 2u);
  EXPECT_EQ(request.fields[0].first, "Host");
  EXPECT_EQ(request.fields[0].second, "127.0.0.1:8080");
  EXPECT_EQ(request.fields[1].second, "image/*");
}

TEST(HttpRequest, SaysWhyAHeadIsMalformed) {
  HttpRequest request;
  EXPECT_EQ(ParseHttpRequest("GET /\r\n\r\n", &request),
            "request line is not METHOD TARGET VERSION");
  EXPECT_EQ(ParseHttpRequest("GET  / HTTP/1.1\r\n\r\n", &request),
            "request line is not METHOD TARGET VERSION");
  EXPECT_EQ(ParseHttpRequest("G(T / HTTP/1.1\r\n\r\n", &request), "bad method");
  EXPECT_EQ(ParseHttpRequest("GET http://x/ HTTP/1.1\r\n\r\n", &request),
            "target is not an absolute path");
  EXPECT_EQ(ParseHttpRequest("GET /\x01 HTTP/1.1\r\n\r\n", &request),
            "control character in target");
  EXPECT_EQ(ParseHttpRequest("GET / HTTP/2\r\n\r\n", &request), "not HTTP/1.0 or HTTP/1.1");
  EXPECT_EQ(ParseHttpRequest("GET / HTTP/1.1\r\nHost x\r\n\r\n", &request),
            "malformed header field");
  EXPECT_EQ(ParseHttpRequest("GET / HTTP/1.1\r\nHost : x\r\n\r\n", &request),
            "malformed header field");
  EXPECT_EQ(ParseHttpRequest("GET / HTTP/1.1\r\n folded\r\n\r\n", &request),
            "malformed header field");
  EXPECT_EQ(ParseHttpRequest("GET / HTTP/1.1\r\nHost: x\r\n", &request),
            "no blank line after the header fields");
}

}  // namespace
}  // namespace viscera::client
