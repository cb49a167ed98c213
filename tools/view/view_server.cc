#include "tools/view/view_server.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netinet/in.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "tools/view/web_assets.h"

namespace semap::tools::view {
namespace {

// Why `host:port` cannot be listened on, found by trying (civetweb says only that it failed): "" if it can.
std::string ProbeListen(const std::string& host, int port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) return "'" + host + "' is not an IPv4 address";
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return std::strerror(errno);
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));  // as civetweb does
  std::string why;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    why = errno == EADDRINUSE ? "already in use" : std::strerror(errno);
  }
  close(fd);
  return why;
}

int SendText(mg_connection* conn, const std::string& text) {
  return mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
}

}  // namespace

void ViewServerOptions::Check() const {
  SEMAP_CHECK_OPTION(!host.empty(), "host", "''", "must not be empty");
  SEMAP_CHECK_OPTION(port >= 0 && port <= 65535, "port", port, "must be in [0, 65535]");
  SEMAP_CHECK_OPTION(push_interval_s > 0.0 && push_interval_s <= 10.0, "push_interval_s", push_interval_s,
                     "must be in (0, 10]");
  SEMAP_CHECK_OPTION(threads >= 2 && threads <= 256, "threads", threads, "must be in [2, 256]");
}

ViewServer::ViewServer(const ViewServerOptions& options, const ViewModel* model)
    : options_(options), model_(model) {
  options_.Check();
  mg_init_library(MG_FEATURES_WEBSOCKET);
  const std::string ports = options_.host + ":" + std::to_string(options_.port);
  const std::string threads = std::to_string(options_.threads);
  // No document root: only the built-in files and the WebSocket are served.
  const char* config[] = {
      "listening_ports", ports.c_str(),       "num_threads", threads.c_str(), "websocket_timeout_ms",
      "3600000",         "enable_keep_alive", "yes",         nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = [](const mg_connection*, const char* message) {
    spdlog::debug("civetweb: {}", message);
    return 1;  // logged here, not by civetweb
  };
  mg_init_data init{&callbacks, this, config};
  char error_text[256] = "";
  unsigned error_code = 0;
  mg_error_data error{&error_code, error_text, sizeof(error_text)};
  context_ = mg_start2(&init, &error);
  if (context_ == nullptr) {
    mg_exit_library();
    const std::string why = options_.port > 0 ? ProbeListen(options_.host, options_.port) : "";
    const std::string where = "port " + std::to_string(options_.port) + " on " + options_.host;
    if (why == "already in use") {
      throw ViewServerError(where +
                            " is already in use (another `semap view`, or another server?): choose a "
                            "free one with --port, or --port 0 for any free port");
    }
    throw ViewServerError("cannot listen on " + where + ": " + (why.empty() ? std::string(error_text) : why));
  }
  mg_server_port bound[4]{};
  const int n = mg_get_server_ports(context_, 4, bound);
  port_ = n > 0 ? bound[0].port : options_.port;
  mg_set_request_handler(context_, "/", &ViewServer::ServeAsset, this);
  mg_set_websocket_handler(context_, "/ws", &ViewServer::OnConnect, &ViewServer::OnReady, &ViewServer::OnData,
                           &ViewServer::OnClose, this);
  pusher_ = std::thread([this] { PushLoop(); });
}

ViewServer::~ViewServer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  pusher_.join();
  mg_stop(context_);  // closes every connection (OnClose runs for each open page)
  mg_exit_library();
}

std::string ViewServer::url() const { return "http://" + options_.host + ":" + std::to_string(port_) + "/"; }

size_t ViewServer::num_clients() const {
  std::lock_guard lock(mutex_);
  return clients_.size();
}

int ViewServer::ServeAsset(mg_connection* conn, void*) {
  const mg_request_info* request = mg_get_request_info(conn);
  const WebAsset* asset = FindWebAsset(request->local_uri != nullptr ? request->local_uri : "");
  if (asset == nullptr) {
    mg_send_http_error(conn, 404, "semap view: no such page: %s", request->local_uri);
    return 404;
  }
  mg_response_header_start(conn, 200);
  mg_response_header_add(conn, "Content-Type", asset->content_type.data(),
                         static_cast<int>(asset->content_type.size()));
  mg_response_header_add(conn, "Cache-Control", "no-store", -1);
  const std::string length = std::to_string(asset->body.size());
  mg_response_header_add(conn, "Content-Length", length.c_str(), -1);
  mg_response_header_send(conn);
  if (std::strcmp(request->request_method, "HEAD") != 0)
    mg_write(conn, asset->body.data(), asset->body.size());
  return 200;
}

int ViewServer::OnConnect(const mg_connection* conn, void* self) {
  auto* server = static_cast<ViewServer*>(self);
  auto client = std::make_unique<Client>();
  client->conn = const_cast<mg_connection*>(conn);
  std::lock_guard lock(server->mutex_);
  server->clients_.push_back(std::move(client));
  return 0;  // accept
}

void ViewServer::OnReady(mg_connection* conn, void* self) {
  auto* server = static_cast<ViewServer*>(self);
  {
    std::lock_guard lock(server->mutex_);
    for (auto& c : server->clients_) {
      if (c->conn == conn) c->ready = true;
    }
  }
  server->wake_.notify_all();
}

int ViewServer::OnData(mg_connection*, int, char*, size_t, void*) {
  return 1;  // the page sends nothing that matters; keep the connection open
}

void ViewServer::OnClose(const mg_connection* conn, void* self) {
  auto* server = static_cast<ViewServer*>(self);
  std::lock_guard lock(server->mutex_);  // waits for a push to this page to end
  std::erase_if(server->clients_, [&](const auto& c) { return c->conn == conn; });
}

void ViewServer::Push(Client* c, const ViewModel::Snapshot& s) {
  mg_lock_connection(c->conn);
  bool ok = true;
  if (!c->hello_sent) {
    ok = SendText(c->conn, model_->hello()) > 0;
    c->hello_sent = ok;
  }
  if (ok && c->epoch != s.epoch) {
    ok = SendText(c->conn, R"({"type":"reset"})") > 0;
    if (ok) {
      c->epoch = s.epoch;
      c->stats_sent = c->poses_sent = 0;
    }
  }
  if (ok && c->status_version != s.status_version) {
    const std::string text = nlohmann::json{{"type", "status"}, {"text", s.status}}.dump();
    ok = SendText(c->conn, text) > 0;
    if (ok) c->status_version = s.status_version;
  }
  if (ok && s.num_poses > c->poses_sent) {
    ok = SendText(c->conn, model_->PosesSince(c->poses_sent, s.num_poses)) > 0;
    if (ok) c->poses_sent = s.num_poses;
  }
  if (ok && s.num_stats > c->stats_sent) {
    ok = SendText(c->conn, model_->StatsSince(c->stats_sent, s.num_stats)) > 0;
    if (ok) c->stats_sent = s.num_stats;
  }
  if (ok && s.mesh && c->mesh_version != s.mesh_version) {  // (a reset's empty mesh is not sent: the page
                                                            // cleared its own)
    ok = mg_websocket_write(c->conn, MG_WEBSOCKET_OPCODE_BINARY, s.mesh->data(), s.mesh->size()) > 0;
    if (ok) c->mesh_version = s.mesh_version;
  }
  mg_unlock_connection(c->conn);
}

void ViewServer::PushLoop() {
  const auto interval = std::chrono::duration<double>(options_.push_interval_s);
  std::unique_lock lock(mutex_);
  while (!stop_) {
    // Each round takes one snapshot; a page that joins later is sent everything at its first round.
    const ViewModel::Snapshot s = model_->Get();
    for (auto& c : clients_) {
      if (c->ready) Push(c.get(), s);
    }
    wake_.wait_for(lock, interval);
  }
}

}  // namespace semap::tools::view
