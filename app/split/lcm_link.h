// The LCM side of a split run: depth-frame datagrams published on, or received from, the channel
// <lcm.channel_prefix>DEPTH_FRAME.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "io/lcm/mesh_blocks.h"

namespace lcm {
class LCM;
}

namespace semap::app {

// The depth frames' channel for a channel prefix.
std::string DepthFrameChannel(const std::string& channel_prefix);

// Publishes datagrams on one channel. Not thread-safe (DepthFramePublisher serialises its calls).
class DepthFrameLcmPublisher {
 public:
  // Throws io::LcmError naming the URL when LCM cannot open it.
  DepthFrameLcmPublisher(const std::string& url, std::string channel);
  ~DepthFrameLcmPublisher();
  // Returns false when LCM refused the datagram (counted by the caller as a send error).
  bool Publish(const io::EncodedMessage& datagram);

 private:
  std::unique_ptr<lcm::LCM> lcm_;
  std::string channel_;
};

// Receives the datagrams of one channel on its own thread and hands each to `on_datagram` (data, size),
// from that thread, until destroyed.
class DepthFrameLcmSubscriber {
 public:
  using OnDatagram = std::function<void(const void* data, size_t size)>;
  // Throws io::LcmError naming the URL when LCM cannot open it.
  DepthFrameLcmSubscriber(const std::string& url, const std::string& channel, OnDatagram on_datagram);
  ~DepthFrameLcmSubscriber();
  DepthFrameLcmSubscriber(const DepthFrameLcmSubscriber&) = delete;
  DepthFrameLcmSubscriber& operator=(const DepthFrameLcmSubscriber&) = delete;

 private:
  std::unique_ptr<lcm::LCM> lcm_;
  OnDatagram on_datagram_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace semap::app
