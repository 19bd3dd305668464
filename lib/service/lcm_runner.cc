#include "service/lcm_runner.h"

#include <spdlog/spdlog.h>

#include <exception>
#include <lcm/lcm-cpp.hpp>
#include <utility>

#include "transport/channels.h"

namespace mvtrack::service {
namespace {

// Raw-bytes handler (free function: LCM 1.3.1's member-function subscribe crashes under UBSan).
void OnRawMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Service* service) {
  try {
    service->OnMessage(channel,
                       static_cast<const std::uint8_t*>(rbuf->data),
                       static_cast<std::size_t>(rbuf->data_size));
  } catch (const std::exception& e) {
    spdlog::error("message on {}: {}", channel, e.what());
  } catch (...) {
    spdlog::error("message on {}: unknown exception", channel);
  }
}

bool IsFileUrl(const std::string& url) { return url.rfind("file://", 0) == 0; }

}  // namespace

std::unique_ptr<LcmRunner> LcmRunner::Create(const DaemonConfig& config, std::string* why) {
  std::unique_ptr<LcmRunner> r(new LcmRunner());
  r->config_ = config;
  r->input_is_file_ = IsFileUrl(config.input_url);
  r->input_ = std::make_unique<lcm::LCM>(config.input_url);
  if (!r->input_->good()) {
    if (why != nullptr) {
      *why = "cannot open the LCM input '" + config.input_url + "'" +
             (r->input_is_file_ ? " (missing, unreadable or empty log?)" : "");
    }
    return nullptr;
  }
  std::string out = config.output_url;
  if (out.empty() && !r->input_is_file_) out = config.input_url;
  r->output_url_ = out;
  if (out.empty()) return r;
  if (out == config.input_url) {
    r->output_ = r->input_.get();
    return r;
  }
  r->own_output_ = std::make_unique<lcm::LCM>(out);
  if (!r->own_output_->good()) {
    if (why != nullptr) *why = "cannot open the LCM output '" + out + "'";
    return nullptr;
  }
  r->output_ = r->own_output_.get();
  return r;
}

LcmRunner::~LcmRunner() = default;

bool LcmRunner::Subscribe(Service* service, std::string* why) {
  std::vector<std::string> channels;
  switch (config_.channel_mode) {
    case ChannelMode::kPerCamera:
      for (const geometry::CameraModel& c : config_.cameras) {
        channels.push_back(transport::DetectionsChannelForCamera(c.id));
      }
      break;
    case ChannelMode::kShared:
      channels.emplace_back(transport::kDetectionsChannel);
      break;
    case ChannelMode::kBoth:
      channels.emplace_back(transport::kDetectionsChannelRegex);
      break;
  }
  for (const std::string& channel : channels) {
    lcm::Subscription* sub = input_->subscribeFunction(channel, &OnRawMessage, service);
    if (sub == nullptr) {
      if (why != nullptr) *why = "cannot subscribe to " + channel;
      return false;
    }
    // LCM queues at most this many received messages per subscription while the handler runs
    // and drops the rest silently (its default, 30, is one frame of 30 cameras).
    sub->setQueueCapacity(LcmQueueCapacity(config_));
  }
  return true;
}

HandleResult LcmRunner::HandleOnce(int timeout_ms) {
  const int status = input_->handleTimeout(timeout_ms);
  if (status > 0) return HandleResult::kMessage;
  if (status == 0) return HandleResult::kTimeout;
  return input_is_file_ ? HandleResult::kEndOfInput : HandleResult::kError;
}

bool LcmRunner::Publish(const std::string& channel, const std::vector<std::uint8_t>& data) {
  if (output_ == nullptr) return true;
  std::lock_guard<std::mutex> lock(publish_mu_);
  return output_->publish(channel, data.data(), static_cast<unsigned int>(data.size())) == 0;
}

}  // namespace mvtrack::service
