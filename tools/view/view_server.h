// The HTTP/WebSocket server of `semap view` (civetweb): serves the page (built into the executable, see
// web_assets.h) and pushes what the ViewModel holds to every open page over a WebSocket (/ws).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tools/view/view_model.h"

struct mg_context;
struct mg_connection;

namespace semap::tools::view {

struct ViewServerOptions {
  // Address to listen on; 127.0.0.1 (the default) keeps the page to this machine.
  std::string host = "127.0.0.1";
  // TCP port; 0 = any free port (the URL printed names it).
  int port = 8080;
  // Pages are sent what changed (mesh, trajectory, statistics, status) this often, seconds.
  double push_interval_s = 0.1;
  // civetweb worker threads: each open page holds one.
  int threads = 8;

  void Check() const;  // throws InvalidOption naming the key and value
};

// The server could not start: the message names the host, the port and why ("already in use").
class ViewServerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Starts listening in the constructor and stops in the destructor. Thread-safe: civetweb's worker threads
// serve requests and WebSocket events, one pusher thread sends updates; both only read the ViewModel (which
// is thread-safe) and share the list of open pages under mutex_.
class ViewServer {
 public:
  // Throws ViewServerError when the address cannot be listened on.
  ViewServer(const ViewServerOptions& options, const ViewModel* model);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  int port() const { return port_; }
  std::string url() const;
  // Pages connected now.
  size_t num_clients() const;

 private:
  struct Client {
    mg_connection* conn = nullptr;
    bool ready = false;  // the WebSocket handshake is complete
    bool hello_sent = false;
    std::uint64_t epoch = 0;
    std::uint64_t mesh_version = 0, status_version = 0;
    size_t stats_sent = 0, poses_sent = 0;
  };
  static int ServeAsset(mg_connection* conn, void* self);
  static int OnConnect(const mg_connection* conn, void* self);
  static void OnReady(mg_connection* conn, void* self);
  static int OnData(mg_connection* conn, int flags, char* data, size_t size, void* self);
  static void OnClose(const mg_connection* conn, void* self);
  void PushLoop();
  void Push(Client* c, const ViewModel::Snapshot& s);

  ViewServerOptions options_;
  const ViewModel* model_;
  mg_context* context_ = nullptr;
  int port_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<std::unique_ptr<Client>> clients_;  // guarded by mutex_
  bool stop_ = false;                             // guarded by mutex_
  std::thread pusher_;
};

}  // namespace semap::tools::view
