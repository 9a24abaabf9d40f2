// The Connect protocol's unary form of koma.v1.Retime on the HTTP port: POST
// /koma.v1.Retime/<Method> with a JSON (application/json, protobuf's JSON mapping) or binary
// (application/proto) body; the answer in the same encoding, or a Connect error
// {"code":"invalid_argument","message":"..."} with the HTTP status Connect gives the code.
// Spec: https://connectrpc.com/docs/protocol (unary request and response, error codes).
//
// Every call goes to the gRPC service itself through the server's in-process channel, so it
// passes the same validation, limits, admission (inline or the worker pool and its
// --max_queued), memory budget (--max_memory_mb), deadline (Connect-Timeout-Ms, then
// --max_call_seconds), logging and metrics as a call on the gRPC port; a binary answer is the
// gRPC answer's bytes.
#ifndef KOMA_SERVER_CONNECT_API_H_
#define KOMA_SERVER_CONNECT_API_H_

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "server/http_server.h"
#include "server/memory_budget.h"

namespace koma::server {

// The path prefix of the service: "/koma.v1.Retime/".
inline constexpr char kConnectServicePrefix[] = "/koma.v1.Retime/";

// Connect's name of a gRPC code: "invalid_argument", "canceled" (Connect's spelling), ...
std::string ConnectCodeName(grpc::StatusCode code);
// The HTTP status Connect maps a code to: invalid_argument 400, resource_exhausted 429,
// deadline_exceeded 504, unimplemented 501, ... (OK: 200).
int ConnectHttpStatus(grpc::StatusCode code);
// A Connect error response: that HTTP status, application/json, {"code":..,"message":..}.
HttpResponse ConnectError(grpc::StatusCode code, absl::string_view message);
// The Connect-Timeout-Ms header's value: a positive integer of at most 10 digits
// (milliseconds), or INVALID_ARGUMENT naming the header and the value.
absl::StatusOr<int64_t> ParseConnectTimeoutMs(absl::string_view value);

// Registers POST kConnectServicePrefix + RetimeSkeletal, RetimeCurves and LipBlink on `http`,
// and a Connect `not_found` (404) for any other method of the service. Calls go through
// `channel` (KomaServer::InProcessChannel()). With a `budget` (null: none), a request's body
// and its parsed copy are reserved from it while the call runs, so a flood of large JSON
// bodies is refused like a flood of large gRPC calls. Both must outlive `http`'s requests.
void RegisterConnectApi(HttpServer& http, std::shared_ptr<grpc::Channel> channel,
                        MemoryBudget* budget);

}  // namespace koma::server

#endif  // KOMA_SERVER_CONNECT_API_H_
