#include "client/vts_messages.h"

#include "absl/strings/str_cat.h"

namespace koma::client {

std::string VtsRequest(std::string_view message_type, std::string_view request_id,
                       const nlohmann::json& data) {
  nlohmann::json request = {
      {"apiName", "VTubeStudioPublicAPI"},
      {"apiVersion", "1.0"},
      {"requestID", std::string(request_id)},
      {"messageType", std::string(message_type)},
      {"data", data},
  };
  return request.dump();
}

std::string VtsTokenRequest(const VtsPlugin& plugin, std::string_view request_id) {
  return VtsRequest("AuthenticationTokenRequest", request_id,
                    {{"pluginName", plugin.name}, {"pluginDeveloper", plugin.developer}});
}

std::string VtsAuthenticationRequest(const VtsPlugin& plugin, std::string_view token,
                                     std::string_view request_id) {
  return VtsRequest("AuthenticationRequest", request_id,
                    {{"pluginName", plugin.name},
                     {"pluginDeveloper", plugin.developer},
                     {"authenticationToken", std::string(token)}});
}

std::string VtsInjectRequest(const std::vector<VtsParameterValue>& values,
                             std::string_view request_id) {
  nlohmann::json parameters = nlohmann::json::array();
  for (const VtsParameterValue& value : values) {
    parameters.push_back({{"id", value.id}, {"value", value.value}});
  }
  return VtsRequest("InjectParameterDataRequest", request_id,
                    {{"faceFound", false}, {"mode", "set"}, {"parameterValues", parameters}});
}

int VtsResponse::error_id() const {
  const auto it = data.find("errorID");
  return it != data.end() && it->is_number_integer() ? it->get<int>() : -1;
}

std::string VtsResponse::error_message() const {
  const auto it = data.find("message");
  return it != data.end() && it->is_string() ? it->get<std::string>() : "";
}

absl::StatusOr<VtsResponse> ParseVtsResponse(std::string_view text) {
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object()) {
    return absl::InvalidArgumentError(
        absl::StrCat("VTube Studio answered with something that is not a JSON object: ",
                     std::string(text.substr(0, 200))));
  }
  VtsResponse response;
  const auto type = json.find("messageType");
  if (type == json.end() || !type->is_string()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "VTube Studio answered without a messageType: ", std::string(text.substr(0, 200))));
  }
  response.message_type = type->get<std::string>();
  const auto id = json.find("requestID");
  if (id != json.end() && id->is_string()) response.request_id = id->get<std::string>();
  const auto data = json.find("data");
  if (data == json.end() || data->is_null()) {
    response.data = nlohmann::json::object();
  } else if (data->is_object()) {
    response.data = *data;
  } else {
    return absl::InvalidArgumentError(absl::StrCat(
        "VTube Studio's ", response.message_type, " has a data that is not an object"));
  }
  return response;
}

}  // namespace koma::client
