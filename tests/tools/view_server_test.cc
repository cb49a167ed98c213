// The pieces of `semap view` without a browser: the mesh message's layout, the view model's versions, and the
// server over plain HTTP (the built-in page, 404, a port in use).
#include "tools/view/view_server.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "tools/view/view_model.h"
#include "tools/view/web_assets.h"

namespace semap::tools::view {
namespace {

Mesh Square() {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 2.5}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.colors_rgb = {{10, 20, 30}, {40, 50, 60}, {70, 80, 90}, {100, 110, 120}};
  m.labels = {1, 3, 3, 9};
  return m;
}

template <typename T>
T At(const std::string& s, size_t offset) {
  T v;
  std::memcpy(&v, s.data() + offset, sizeof(T));
  return v;
}

TEST(ViewMeshMessage, LayoutAsThePageReadsIt) {
  const Mesh m = Square();
  const std::vector<float> error = {0.f, 0.1f, 0.2f, 3.f};
  const std::string msg = EncodeMeshMessage(m, 41, &error);
  ASSERT_EQ(msg.size(), 24u + 4 * 12 + 4 * 4 + 2 * 12 + 4 * 3 + 4);
  EXPECT_EQ(msg.substr(0, 4), "SMV1");
  EXPECT_EQ(At<std::uint32_t>(msg, 4), 4u);
  EXPECT_EQ(At<std::uint32_t>(msg, 8), 2u);
  EXPECT_EQ(At<std::uint32_t>(msg, 12), 1u);  // error present
  EXPECT_EQ(At<std::int64_t>(msg, 16), 41);
  EXPECT_EQ(At<float>(msg, 24 + 3 * 12 + 8), 2.5f);                     // z of vertex 3
  EXPECT_EQ(At<float>(msg, 24 + 48 + 12), 3.f);                         // error of vertex 3
  EXPECT_EQ(At<std::uint32_t>(msg, 24 + 64 + 5 * 4), 3u);               // last index
  EXPECT_EQ(static_cast<std::uint8_t>(msg[24 + 64 + 24 + 3]), 40);      // red of vertex 1
  EXPECT_EQ(static_cast<std::uint8_t>(msg[24 + 64 + 24 + 12 + 3]), 9);  // label of vertex 3
  // Without error (or with one of the wrong size) the flag is clear and the block absent.
  const std::vector<float> wrong = {1.f};
  EXPECT_EQ(EncodeMeshMessage(m, -1, &wrong).size(), msg.size() - 16);
  EXPECT_EQ(At<std::uint32_t>(EncodeMeshMessage(m, -1, nullptr), 12), 0u);
}

TEST(ViewModelTest, VersionsRangesAndReset) {
  ViewModel model(SourceInfo{"live", "udpm://x", "auto", false, ""}, ClassMap::Cityscapes());
  const auto hello = nlohmann::json::parse(model.hello());
  EXPECT_EQ(hello["type"], "hello");
  EXPECT_EQ(hello["palette"].size(), ClassMap::Cityscapes().classes().size());
  EXPECT_EQ(model.Get().mesh_version, 0u);
  model.SetMesh(std::make_shared<const std::string>("m"), 2, 4);
  for (int i = 0; i < 3; ++i) model.AddStats({i, 0.1 * i, 5.0, 10 * i, 5 * i});
  model.AddPose({7, Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond::Identity()});
  auto s = model.Get();
  EXPECT_EQ(s.mesh_version, 1u);
  EXPECT_EQ(s.triangles, 2);
  EXPECT_EQ(s.num_stats, 3u);
  EXPECT_EQ(nlohmann::json::parse(model.StatsSince(1, 3))["points"].size(), 2u);
  EXPECT_EQ(nlohmann::json::parse(model.StatsSince(1, 99))["points"].size(), 2u);
  EXPECT_EQ(model.StatsSince(3, 3), "");
  EXPECT_EQ(nlohmann::json::parse(model.PosesSince(0, 1))["points"][0][1], 1.0);
  model.SetStatus("a");
  const auto v = model.Get().status_version;
  model.SetStatus("a");  // unchanged: same version
  EXPECT_EQ(model.Get().status_version, v);
  model.Reset();
  s = model.Get();
  EXPECT_EQ(s.epoch, 1u);
  EXPECT_EQ(s.num_stats, 0u);
  EXPECT_EQ(s.num_poses, 0u);
  EXPECT_EQ(s.mesh, nullptr);
}

// GET `path` from 127.0.0.1:port: the whole response (headers and body).
std::string HttpGet(int port, const std::string& path) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    close(fd);
    return "";
  }
  const std::string request = "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  if (write(fd, request.data(), request.size()) != static_cast<ssize_t>(request.size())) {
    close(fd);
    return "";
  }
  std::string response;
  char buf[65536];
  ssize_t n = 0;
  while ((n = read(fd, buf, sizeof(buf))) > 0) response.append(buf, static_cast<size_t>(n));
  close(fd);
  return response;
}

TEST(ViewServerTest, ServesTheBuiltInPageAndNamesATakenPort) {
  ViewModel model(SourceInfo{"mesh", "m.ply", "auto", false, ""}, ClassMap::Cityscapes());
  ViewServerOptions options;
  options.port = 0;
  ViewServer server(options, &model);
  ASSERT_GT(server.port(), 0);
  EXPECT_EQ(server.url(), "http://127.0.0.1:" + std::to_string(server.port()) + "/");
  const std::string index = HttpGet(server.port(), "/");
  EXPECT_NE(index.find("200 OK"), std::string::npos) << index.substr(0, 200);
  EXPECT_NE(index.find("text/html"), std::string::npos);
  EXPECT_NE(index.find("<title>semap view</title>"), std::string::npos);
  EXPECT_NE(index.find("id=\"triangles\""), std::string::npos);
  const std::string app = HttpGet(server.port(), "/app.js");
  const WebAsset* asset = FindWebAsset("/app.js");
  ASSERT_NE(asset, nullptr);
  EXPECT_GT(asset->body.size(), 100000u);  // three.js bundled
  EXPECT_EQ(app.substr(app.size() - asset->body.size()), asset->body);
  EXPECT_NE(HttpGet(server.port(), "/app.js.LEGAL.txt").find("MIT"), std::string::npos);
  EXPECT_NE(HttpGet(server.port(), "/../etc/passwd").find("404"), std::string::npos);
  EXPECT_NE(HttpGet(server.port(), "/nope").find("404"), std::string::npos);

  ViewServerOptions same = options;
  same.port = server.port();
  try {
    ViewServer second(same, &model);
    FAIL() << "a second server on the same port started";
  } catch (const ViewServerError& e) {
    EXPECT_NE(std::string(e.what()).find("port " + std::to_string(server.port()) +
                                         " on 127.0.0.1 is already in use"),
              std::string::npos)
        << e.what();
  }
  ViewServerOptions bad = options;
  bad.port = 70000;
  EXPECT_THROW({ ViewServer rejected(bad, &model); }, InvalidOption);
}

}  // namespace
}  // namespace semap::tools::view
