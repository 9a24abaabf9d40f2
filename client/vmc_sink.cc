#include "client/vmc_sink.h"

#include <lo/lo.h>

#include <cstdio>
#include <cstdlib>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace koma::client {
namespace {

constexpr char kBlendValue[] = "/VMC/Ext/Blend/Val";
constexpr char kBlendApply[] = "/VMC/Ext/Blend/Apply";

// The bundle of `blends` then Apply, time tag "immediately" (a receiver applies it on arrival;
// the frame's time is already the moment it is sent). Freed with lo_bundle_free_recursive.
lo_bundle NewVmcBundle(const std::vector<VmcBlend>& blends) {
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  for (const VmcBlend& blend : blends) {
    lo_message message = lo_message_new();
    lo_message_add_string(message, blend.clip.c_str());
    lo_message_add_float(message, blend.value);
    lo_bundle_add_message(bundle, kBlendValue, message);
  }
  lo_bundle_add_message(bundle, kBlendApply, lo_message_new());
  return bundle;
}

}  // namespace

absl::Status ParseVmcTarget(const std::string& target, const char* flag, VmcOptions& options) {
  if (target.empty()) return ParseVmcTarget(kVmcDefaultTarget, flag, options);
  std::string host;
  std::string port;
  if (target.front() == '[') {  // [IPv6]:PORT
    const size_t close = target.find(']');
    if (close == std::string::npos || close + 1 >= target.size() || target[close + 1] != ':') {
      return absl::InvalidArgumentError(
          absl::StrCat(flag, ": \"", target, "\" must be HOST:PORT or [IPv6]:PORT"));
    }
    host = target.substr(1, close - 1);
    port = target.substr(close + 2);
  } else {
    const size_t colon = target.rfind(':');
    if (colon == std::string::npos || target.find(':') != colon) {
      return absl::InvalidArgumentError(
          absl::StrCat(flag, ": \"", target, "\" must be HOST:PORT (127.0.0.1:39539)"));
    }
    host = target.substr(0, colon);
    port = target.substr(colon + 1);
  }
  int number = 0;
  if (host.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(flag, ": \"", target, "\" has no host"));
  }
  if (!absl::SimpleAtoi(port, &number) || number < 1 || number > 65535 ||
      port.find_first_not_of("0123456789") != std::string::npos) {
    return absl::InvalidArgumentError(
        absl::StrCat(flag, ": port \"", port, "\" must be a number in [1, 65535]"));
  }
  options.host = host;
  options.port = port;
  return absl::OkStatus();
}

std::vector<VmcBlend> VmcBlendsOf(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels,
                                  const VmcOptions& options) {
  return {
      {options.mouth_clip, static_cast<float>(MouthOpenness(frame, levels))},
      {options.blink_clip, static_cast<float>(1.0 - EyeOpenness(frame, levels))},
  };
}

std::string VmcBundleBytes(const std::vector<VmcBlend>& blends) {
  lo_bundle bundle = NewVmcBundle(blends);
  size_t size = 0;
  void* bytes = lo_bundle_serialise(bundle, nullptr, &size);
  std::string out(static_cast<const char*>(bytes), size);
  std::free(bytes);
  lo_bundle_free_recursive(bundle);
  return out;
}

absl::StatusOr<std::unique_ptr<VmcSink>> VmcSink::Open(const VmcOptions& options) {
  lo_address address = lo_address_new(options.host.c_str(), options.port.c_str());
  if (address == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("--vmc: cannot use ", options.host, ":", options.port));
  }
  return std::unique_ptr<VmcSink>(new VmcSink(options, address));
}

VmcSink::VmcSink(const VmcOptions& options, void* address)
    : options_(options), address_(address) {}

VmcSink::~VmcSink() { lo_address_free(static_cast<lo_address>(address_)); }

absl::Status VmcSink::Start(const v1::LiveLipBlinkSetup& setup) {
  levels_ = AvatarLevelsOf(setup);
  return absl::OkStatus();
}

absl::Status VmcSink::Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) {
  (void)timing;
  lo_address address = static_cast<lo_address>(address_);
  lo_bundle bundle = NewVmcBundle(VmcBlendsOf(frame, levels_, options_));
  const int sent = lo_send_bundle(address, bundle);
  lo_bundle_free_recursive(bundle);
  if (sent >= 0) {
    ++bundles_sent_;
    return absl::OkStatus();
  }
  // UDP: a lost frame is replaced by the next one 1/24 s later; warn once, keep streaming.
  if (bundles_lost_++ == 0) {
    const char* error = lo_address_errstr(address);
    std::fprintf(stderr, "koma: warning: --vmc: cannot send to %s:%s (%s); going on\n",
                 options_.host.c_str(), options_.port.c_str(), error ? error : "unknown error");
  }
  return absl::OkStatus();
}

absl::Status VmcSink::Close() {
  if (bundles_lost_ > 0) {
    std::fprintf(stderr, "koma: warning: --vmc: %lld of %lld frames were not sent to %s:%s\n",
                 static_cast<long long>(bundles_lost_),
                 static_cast<long long>(bundles_lost_ + bundles_sent_), options_.host.c_str(),
                 options_.port.c_str());
  }
  return absl::OkStatus();
}

}  // namespace koma::client
