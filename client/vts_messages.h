// VTube Studio's public API messages (github.com/DenchiSoft/VTubeStudio, README "API
// Details"): JSON text over a WebSocket. Every request carries apiName "VTubeStudioPublicAPI",
// apiVersion "1.0", a requestID (1..64 ASCII characters), its messageType and data; every
// response the same names, an answering messageType ("...Response", or "APIError" with
// errorID and message). Only what `koma live --vts` sends and reads is here.
#ifndef KOMA_CLIENT_VTS_MESSAGES_H_
#define KOMA_CLIENT_VTS_MESSAGES_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "nlohmann/json.hpp"

namespace koma::client {

// Who asks: VTube Studio shows both in its "allow this plugin?" popup; each 3..32 characters,
// and a token is valid only for the names it was issued to.
struct VtsPlugin {
  std::string name = "koma";
  std::string developer = "koma contributors";
};

// One injected input parameter (a default one such as MouthOpen, or a plugin's custom one).
struct VtsParameterValue {
  std::string id;
  double value = 0.0;  // VTube Studio takes -1,000,000 .. 1,000,000; ours are 0..1
};

// A request's JSON text.
std::string VtsRequest(std::string_view message_type, std::string_view request_id,
                       const nlohmann::json& data);

// AuthenticationTokenRequest: VTube Studio asks the user to allow the plugin (no icon).
std::string VtsTokenRequest(const VtsPlugin& plugin, std::string_view request_id);
// AuthenticationRequest: this session, with a token issued before.
std::string VtsAuthenticationRequest(const VtsPlugin& plugin, std::string_view token,
                                     std::string_view request_id);
// InjectParameterDataRequest with faceFound false (the face tracker, if any, decides whether
// the "tracking lost" animation plays) and mode "set" (the values replace the tracker's).
std::string VtsInjectRequest(const std::vector<VtsParameterValue>& values,
                             std::string_view request_id);

// A response, as far as koma reads one.
struct VtsResponse {
  std::string message_type;  // "AuthenticationTokenResponse", "APIError", ...
  std::string request_id;
  nlohmann::json data;       // an object (empty when the response had none)
  bool is_error() const { return message_type == "APIError"; }
  int error_id() const;               // data.errorID (-1 when absent)
  std::string error_message() const;  // data.message ("" when absent)
};

// INVALID_ARGUMENT for text that is not a JSON object with a string messageType, or whose data
// is present and not an object.
absl::StatusOr<VtsResponse> ParseVtsResponse(std::string_view text);

}  // namespace koma::client

#endif  // KOMA_CLIENT_VTS_MESSAGES_H_
