#pragma once
/// @file
/// LcmRunner: the LCM edge of the daemon. It opens the input (and, when different, the output)
/// LCM instance from a DaemonConfig, subscribes the detections channels with raw-bytes handlers
/// (never the typed or member-function overloads; see transport/codec.h) that hand the bytes to
/// Service::OnMessage, dispatches messages on the calling thread, and publishes encoded
/// messages.
///
/// Output URL rules: "" means the input URL, except for a file:// input (a log opened for
/// reading cannot publish), where "" means no LCM output. A file:// input is read as the URL
/// says (add `speed=0` to read as fast as the daemon consumes); its end is reported by
/// HandleOnce() as kEndOfInput.
///
/// Thread safety: Subscribe and HandleOnce on the control thread only; Publish is thread-safe
/// (serialised internally) and may run concurrently with HandleOnce.

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "service/daemon_config.h"
#include "service/service.h"

namespace lcm {
class LCM;
}  // namespace lcm

namespace mvtrack::service {

/// What one HandleOnce() did.
enum class HandleResult {
  kMessage,     ///< dispatched one message
  kTimeout,     ///< nothing arrived within the timeout
  kEndOfInput,  ///< a file:// input reached the end of its log
  kError,       ///< LCM reported an error (the input is unusable)
};

/// The LCM edge; see the file comment.
class LcmRunner {
 public:
  /// Opens the LCM instances. Returns nullptr with `why` set when LCM cannot be initialised
  /// (bad URL, missing or empty log file, network unavailable).
  static std::unique_ptr<LcmRunner> Create(const DaemonConfig& config, std::string* why);
  ~LcmRunner();
  LcmRunner(const LcmRunner&) = delete;
  LcmRunner& operator=(const LcmRunner&) = delete;

  /// Subscribes the detections channels of `config.channel_mode` (per-camera channels of the
  /// configured cameras, the shared channel, or both) and routes every message to `service`,
  /// which must outlive the subscriptions (they end with the runner). Returns false with `why`
  /// set when LCM refuses a subscription.
  bool Subscribe(Service* service, std::string* why);

  /// Waits up to `timeout_ms` for a message and dispatches it on this thread.
  HandleResult HandleOnce(int timeout_ms);

  /// Publishes on the output instance (no-op without LCM output). Thread-safe. Returns false
  /// when LCM reports a failure.
  bool Publish(const std::string& channel, const std::vector<std::uint8_t>& data);

  /// True when there is an LCM output.
  bool has_output() const { return output_ != nullptr; }
  /// True when the input is a file:// log.
  bool input_is_file() const { return input_is_file_; }
  /// The effective output URL ("" without LCM output).
  const std::string& output_url() const { return output_url_; }

 private:
  LcmRunner() = default;

  std::unique_ptr<lcm::LCM> input_;
  std::unique_ptr<lcm::LCM> own_output_;  // when the output URL differs from the input's
  lcm::LCM* output_ = nullptr;
  std::mutex publish_mu_;
  bool input_is_file_ = false;
  std::string output_url_;
  DaemonConfig config_;
};

}  // namespace mvtrack::service
