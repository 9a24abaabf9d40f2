#include "server/connect_api.h"

#include <google/protobuf/util/json_util.h>
#include <grpcpp/generic/generic_stub.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "koma/v1/retime.pb.h"

namespace koma::server {
namespace {

constexpr char kJson[] = "application/json";
constexpr char kProto[] = "application/proto";

// The media type without parameters, lower-cased: "application/json; charset=utf-8" ->
// "application/json".
std::string MediaType(const std::string* content_type) {
  if (content_type == nullptr) return "";
  const size_t semicolon = content_type->find(';');
  return absl::AsciiStrToLower(
      absl::StripAsciiWhitespace(absl::string_view(*content_type).substr(0, semicolon)));
}

// An x-request-id a client sent, if gRPC metadata can carry it (printable ASCII, bounded);
// the service logs it and sends it back (server/logging.h).
bool UsableRequestId(const std::string& id) {
  if (id.empty() || id.size() > 128) return false;
  for (char c : id) {
    if (c < 0x20 || c > 0x7e) return false;
  }
  return true;
}

// One unary call on the in-process channel, waited for on this (civetweb's) thread.
grpc::Status CallInProcess(grpc::GenericStub& stub, grpc::ClientContext& context,
                           const std::string& method_path, std::string request_bytes,
                           std::string* response_bytes) {
  grpc::Slice slice(std::move(request_bytes));
  const grpc::ByteBuffer request(&slice, 1);
  grpc::ByteBuffer response;
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  grpc::Status status;
  stub.UnaryCall(&context, method_path, grpc::StubOptions(), &request, &response,
                 [&](grpc::Status s) {
                   std::lock_guard lock(mutex);
                   status = std::move(s);
                   done = true;
                   done_cv.notify_one();
                 });
  {
    std::unique_lock lock(mutex);
    done_cv.wait(lock, [&] { return done; });
  }
  if (status.ok()) {
    std::vector<grpc::Slice> slices;
    if (!response.Dump(&slices).ok()) {
      return grpc::Status(grpc::StatusCode::INTERNAL, "response: could not be read");
    }
    response_bytes->clear();
    response_bytes->reserve(response.Length());
    for (const grpc::Slice& s : slices) {
      response_bytes->append(reinterpret_cast<const char*>(s.begin()), s.size());
    }
  }
  return status;
}

// One method of the service on the HTTP port.
template <typename Request, typename Response>
class ConnectMethod {
 public:
  ConnectMethod(std::string name, std::shared_ptr<grpc::GenericStub> stub, MemoryBudget* budget)
      : path_(std::string(kConnectServicePrefix) + name), stub_(std::move(stub)), budget_(budget) {}

  HttpResponse operator()(const HttpRequest& http) const {
    const std::string media_type = MediaType(http.Header("content-type"));
    const bool json = media_type == kJson;
    if (!json && media_type != kProto) {
      HttpResponse response = ConnectError(
          grpc::StatusCode::INVALID_ARGUMENT,
          absl::StrCat("Content-Type: \"", media_type, "\" is not supported; send ", kJson,
                       " (protobuf's JSON mapping) or ", kProto, " (binary protobuf)"));
      response.status = 415;
      response.SetHeader("Accept-Post", absl::StrCat(kJson, ", ", kProto));
      return response;
    }
    if (const std::string* version = http.Header("connect-protocol-version");
        version != nullptr && *version != "1") {
      return ConnectError(grpc::StatusCode::INVALID_ARGUMENT,
                          absl::StrCat("Connect-Protocol-Version: \"", *version,
                                       "\" is not supported; this server speaks version 1"));
    }
    if (const std::string* encoding = http.Header("content-encoding");
        encoding != nullptr && absl::AsciiStrToLower(*encoding) != "identity") {
      HttpResponse response = ConnectError(
          grpc::StatusCode::UNIMPLEMENTED,
          absl::StrCat("Content-Encoding: \"", *encoding,
                       "\" is not supported; send the body uncompressed (identity)"));
      response.SetHeader("Accept-Encoding", "identity");
      return response;
    }
    grpc::ClientContext context;
    if (const std::string* timeout = http.Header("connect-timeout-ms"); timeout != nullptr) {
      const absl::StatusOr<int64_t> ms = ParseConnectTimeoutMs(*timeout);
      if (!ms.ok()) {
        return ConnectError(grpc::StatusCode::INVALID_ARGUMENT, ms.status().message());
      }
      context.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(*ms));
    }
    if (const std::string* id = http.Header("x-request-id"); id != nullptr && UsableRequestId(*id)) {
      context.AddMetadata("x-request-id", *id);
    }
    // The body, and for JSON the parsed message and its serialised bytes, are held while the
    // call runs: reserve them beside what the service reserves for the call itself.
    MemoryBudget::Reservation reservation;
    if (budget_ != nullptr) {
      const int64_t held = static_cast<int64_t>(http.body.size()) * (json ? 3 : 2);
      absl::StatusOr<MemoryBudget::Reservation> reserved =
          budget_->Reserve(held, "the HTTP request body");
      if (!reserved.ok()) {
        return ConnectError(grpc::StatusCode::RESOURCE_EXHAUSTED, reserved.status().message());
      }
      reservation = *std::move(reserved);
    }
    std::string request_bytes;
    if (json) {
      Request request;
      google::protobuf::util::JsonParseOptions options;
      options.ignore_unknown_fields = false;  // a misspelt field is an error, not a default
      const auto parsed = google::protobuf::util::JsonStringToMessage(http.body, &request, options);
      if (!parsed.ok()) {
        return ConnectError(grpc::StatusCode::INVALID_ARGUMENT,
                            absl::StrCat("request body: not a ", Request::descriptor()->full_name(),
                                         " in JSON: ", std::string(parsed.message())));
      }
      if (!request.SerializeToString(&request_bytes)) {
        return ConnectError(grpc::StatusCode::INVALID_ARGUMENT,
                            "request body: the message is over protobuf's 2 GiB limit");
      }
    } else {
      request_bytes = http.body;
    }
    std::string response_bytes;
    const grpc::Status status =
        CallInProcess(*stub_, context, path_, std::move(request_bytes), &response_bytes);
    HttpResponse response;
    if (!status.ok()) {
      response = ConnectError(status.error_code(), status.error_message());
    } else if (json) {
      Response message;
      std::string text;
      if (!message.ParseFromString(response_bytes) ||
          !google::protobuf::util::MessageToJsonString(message, &text).ok()) {
        response = ConnectError(grpc::StatusCode::INTERNAL,
                                "response: could not be written as JSON");
      } else {
        response.SetHeader("Content-Type", kJson);
        response.body = std::move(text);
      }
    } else {
      response.SetHeader("Content-Type", kProto);
      response.body = std::move(response_bytes);
    }
    const auto& metadata = context.GetServerInitialMetadata();
    if (const auto id = metadata.find("x-request-id"); id != metadata.end()) {
      response.SetHeader("X-Request-Id", std::string(id->second.data(), id->second.size()));
    }
    response.SetHeader("Cache-Control", "no-store");
    return response;
  }

 private:
  const std::string path_;
  const std::shared_ptr<grpc::GenericStub> stub_;
  MemoryBudget* const budget_;
};

template <typename Request, typename Response>
void Register(HttpServer& http, const char* name, const std::shared_ptr<grpc::GenericStub>& stub,
              MemoryBudget* budget) {
  http.Handle("POST", std::string(kConnectServicePrefix) + name,
              ConnectMethod<Request, Response>(name, stub, budget));
}

}  // namespace

std::string ConnectCodeName(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return "ok";
    case grpc::StatusCode::CANCELLED: return "canceled";
    case grpc::StatusCode::UNKNOWN: return "unknown";
    case grpc::StatusCode::INVALID_ARGUMENT: return "invalid_argument";
    case grpc::StatusCode::DEADLINE_EXCEEDED: return "deadline_exceeded";
    case grpc::StatusCode::NOT_FOUND: return "not_found";
    case grpc::StatusCode::ALREADY_EXISTS: return "already_exists";
    case grpc::StatusCode::PERMISSION_DENIED: return "permission_denied";
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return "resource_exhausted";
    case grpc::StatusCode::FAILED_PRECONDITION: return "failed_precondition";
    case grpc::StatusCode::ABORTED: return "aborted";
    case grpc::StatusCode::OUT_OF_RANGE: return "out_of_range";
    case grpc::StatusCode::UNIMPLEMENTED: return "unimplemented";
    case grpc::StatusCode::INTERNAL: return "internal";
    case grpc::StatusCode::UNAVAILABLE: return "unavailable";
    case grpc::StatusCode::DATA_LOSS: return "data_loss";
    case grpc::StatusCode::UNAUTHENTICATED: return "unauthenticated";
    default: return "unknown";
  }
}

int ConnectHttpStatus(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return 200;
    case grpc::StatusCode::CANCELLED: return 499;
    case grpc::StatusCode::INVALID_ARGUMENT: return 400;
    case grpc::StatusCode::DEADLINE_EXCEEDED: return 504;
    case grpc::StatusCode::NOT_FOUND: return 404;
    case grpc::StatusCode::ALREADY_EXISTS: return 409;
    case grpc::StatusCode::PERMISSION_DENIED: return 403;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return 429;
    case grpc::StatusCode::FAILED_PRECONDITION: return 400;
    case grpc::StatusCode::ABORTED: return 409;
    case grpc::StatusCode::OUT_OF_RANGE: return 400;
    case grpc::StatusCode::UNIMPLEMENTED: return 501;
    case grpc::StatusCode::UNAVAILABLE: return 503;
    case grpc::StatusCode::UNAUTHENTICATED: return 401;
    default: return 500;  // unknown, internal, data_loss
  }
}

HttpResponse ConnectError(grpc::StatusCode code, absl::string_view message) {
  return JsonError(ConnectHttpStatus(code), ConnectCodeName(code), message);
}

absl::StatusOr<int64_t> ParseConnectTimeoutMs(absl::string_view value) {
  int64_t ms = 0;
  bool digits = !value.empty() && value.size() <= 10;
  for (char c : value) digits = digits && absl::ascii_isdigit(static_cast<unsigned char>(c));
  if (!digits || !absl::SimpleAtoi(value, &ms) || ms <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("Connect-Timeout-Ms: \"", value,
                     "\" is not a positive whole number of milliseconds (at most 10 digits)"));
  }
  return ms;
}

void RegisterConnectApi(HttpServer& http, std::shared_ptr<grpc::Channel> channel,
                        MemoryBudget* budget) {
  auto stub = std::make_shared<grpc::GenericStub>(std::move(channel));
  Register<v1::RetimeSkeletalRequest, v1::RetimeSkeletalResponse>(http, "RetimeSkeletal", stub,
                                                                  budget);
  Register<v1::RetimeCurvesRequest, v1::RetimeCurvesResponse>(http, "RetimeCurves", stub, budget);
  Register<v1::LipBlinkRequest, v1::LipBlinkResponse>(http, "LipBlink", stub, budget);
  http.HandlePrefix("POST", kConnectServicePrefix, [](const HttpRequest& request) {
    return ConnectError(
        grpc::StatusCode::NOT_FOUND,
        absl::StrCat(request.path,
                     ": no such method; koma.v1.Retime's unary methods are RetimeSkeletal, "
                     "RetimeCurves and LipBlink (LiveLipBlink is a stream: gRPC only)"));
  });
}

}  // namespace koma::server
