#include "app/split/lcm_link.h"

#include <lcm/lcm-cpp.hpp>

#include "io/lcm/lcm_publisher.h"

namespace semap::app {

namespace {
// The receiving thread looks at its stop flag this often, ms.
constexpr int kHandleTimeoutMs = 100;
}  // namespace

std::string DepthFrameChannel(const std::string& channel_prefix) { return channel_prefix + "DEPTH_FRAME"; }

DepthFrameLcmPublisher::DepthFrameLcmPublisher(const std::string& url, std::string channel)
    : lcm_(std::make_unique<lcm::LCM>(url)), channel_(std::move(channel)) {
  if (!lcm_->good()) throw io::LcmError("cannot open LCM URL '" + url + "'");
}

DepthFrameLcmPublisher::~DepthFrameLcmPublisher() = default;

bool DepthFrameLcmPublisher::Publish(const io::EncodedMessage& datagram) {
  return lcm_->publish(channel_, datagram.data(), static_cast<unsigned int>(datagram.size())) == 0;
}

DepthFrameLcmSubscriber::DepthFrameLcmSubscriber(const std::string& url, const std::string& channel,
                                                 OnDatagram on_datagram)
    : lcm_(std::make_unique<lcm::LCM>(url)), on_datagram_(std::move(on_datagram)) {
  if (!lcm_->good()) throw io::LcmError("cannot open LCM URL '" + url + "'");
  const auto handler = [](const lcm::ReceiveBuffer* rbuf, const std::string&, DepthFrameLcmSubscriber* self) {
    self->on_datagram_(rbuf->data, rbuf->data_size);
  };
  lcm_->subscribeFunction<DepthFrameLcmSubscriber*>(channel, handler, this);
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      if (lcm_->handleTimeout(kHandleTimeoutMs) < 0) break;
    }
  });
}

DepthFrameLcmSubscriber::~DepthFrameLcmSubscriber() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

}  // namespace semap::app
