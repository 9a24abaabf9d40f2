// The Connect API and the HTTP server's routing, in process: HttpServer::Respond is what the
// civetweb callback sends (the socket side is tests/e2e/http_api_e2e_test.sh). Each RPC in
// JSON and binary against the gRPC answer of the same request, the Connect errors, the
// security and CORS headers, the shared memory budget.
#include "server/connect_api.h"

#include <google/protobuf/util/json_util.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server/http_server.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"
#include "tests/server/lip_blink_request_builder.h"
#include "tests/server/request_builder.h"

namespace koma::testing {
namespace {

using server::HttpRequest;
using server::HttpResponse;

// A server with its HTTP port on loopback (port 0: a free one), shared by a suite's cases
// (civetweb's stop takes up to 2 s: its listener polls in 2 s quanta); requests go to Respond.
class ConnectTest : public ::testing::Test {
 protected:
  static server::ServerConfig Config() {
    server::ServerConfig config;
    config.address = "";
    config.worker_threads = 1;
    config.http.port = 0;
    return config;
  }
  static void SetUpTestSuite() { Start(Config()); }
  static void Start(const server::ServerConfig& config) {
    server_ = server::KomaServer::Start(config).value().release();
    stub_ = v1::Retime::NewStub(server_->InProcessChannel()).release();
  }
  static void TearDownTestSuite() {
    delete stub_;
    delete server_;
    stub_ = nullptr;
    server_ = nullptr;
  }

  static HttpResponse Post(const std::string& method, const std::string& content_type,
                           const std::string& body) {
    HttpRequest request;
    request.method = "POST";
    request.path = "/koma.v1.Retime/" + method;
    if (!content_type.empty()) request.headers.emplace_back("content-type", content_type);
    request.body = body;
    return server_->http_server()->Respond(request);
  }
  template <typename Request>
  static HttpResponse PostJson(const std::string& method, const Request& request) {
    std::string json;
    EXPECT_TRUE(google::protobuf::util::MessageToJsonString(request, &json).ok());
    return Post(method, "application/json", json);
  }

  static inline server::KomaServer* server_ = nullptr;
  static inline v1::Retime::Stub* stub_ = nullptr;
};

const std::string* HeaderOf(const HttpResponse& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return &value;
  }
  return nullptr;
}

// The Connect error body's code and message.
std::pair<std::string, std::string> ErrorOf(const HttpResponse& response) {
  const nlohmann::json error = nlohmann::json::parse(response.body);
  return {error.at("code").get<std::string>(), error.at("message").get<std::string>()};
}

// The JSON answer parses to the gRPC answer of the same request, and so does the binary one.
TEST_F(ConnectTest, EachRpcInJsonAndBinaryAnswersAsGrpc) {
  const auto check = [&](const std::string& method, const auto& request, auto grpc_response) {
    SCOPED_TRACE(method);
    ASSERT_TRUE(CallRpc(*stub_, request, &grpc_response).ok());

    const HttpResponse json = PostJson(method, request);
    ASSERT_EQ(json.status, 200) << json.body;
    EXPECT_EQ(*HeaderOf(json, "Content-Type"), "application/json");
    decltype(grpc_response) from_json;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(json.body, &from_json).ok());
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(from_json, grpc_response));

    const HttpResponse binary =
        Post(method, "application/proto", request.SerializeAsString());
    ASSERT_EQ(binary.status, 200) << binary.body;
    EXPECT_EQ(*HeaderOf(binary, "Content-Type"), "application/proto");
    decltype(grpc_response) from_binary;
    ASSERT_TRUE(from_binary.ParseFromString(binary.body));
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(from_binary, grpc_response));
  };
  check("RetimeSkeletal", MakeSkeletalRequest(40), v1::RetimeSkeletalResponse());
  check("RetimeCurves", MakeCurvesRequest(), v1::RetimeCurvesResponse());
  check("LipBlink", MakeLipBlinkRequest(), v1::LipBlinkResponse());
}

TEST_F(ConnectTest, BinaryAnswerIsTheGrpcAnswersBytes) {
  // The raw gRPC bytes (the service writes RetimeSkeletal's and RetimeCurves' answers itself,
  // so they are compared as bytes, not re-serialised).
  InProcessServer grpc_server;
  const struct {
    const char* method;
    std::string request;
  } cases[] = {
      {"RetimeSkeletal", MakeSkeletalRequest(40).SerializeAsString()},
      {"RetimeCurves", MakeCurvesRequest().SerializeAsString()},
      {"LipBlink", MakeLipBlinkRequest().SerializeAsString()},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.method);
    std::string grpc_bytes;
    ASSERT_TRUE(RawUnaryCall(grpc_server, std::string("/koma.v1.Retime/") + c.method, c.request,
                             &grpc_bytes)
                    .ok());
    const HttpResponse binary = Post(c.method, "application/proto", c.request);
    ASSERT_EQ(binary.status, 200) << binary.body;
    EXPECT_EQ(binary.body, grpc_bytes);
  }
}

TEST_F(ConnectTest, ServiceErrorsAreConnectErrorsWithTheGrpcMessage) {
  v1::RetimeCurvesRequest request = MakeCurvesRequest();
  request.mutable_curves()->set_fps(-1);
  v1::RetimeCurvesResponse unused;
  const grpc::Status grpc_status = CallRpc(*stub_, request, &unused);
  ASSERT_EQ(grpc_status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  for (const bool json : {true, false}) {
    const HttpResponse response = json ? PostJson("RetimeCurves", request)
                                       : Post("RetimeCurves", "application/proto",
                                              request.SerializeAsString());
    EXPECT_EQ(response.status, 400);
    EXPECT_EQ(*HeaderOf(response, "Content-Type"), "application/json");
    EXPECT_EQ(ErrorOf(response), std::make_pair(std::string("invalid_argument"),
                                                grpc_status.error_message()));
  }
  // Binary bytes that are not the message: the service's own parse error.
  const HttpResponse garbage = Post("LipBlink", "application/proto", "\xff\xff\xff");
  EXPECT_EQ(garbage.status, 400);
  EXPECT_EQ(ErrorOf(garbage).second,
            "request: the bytes are not a valid koma.v1.LipBlinkRequest (protobuf parse failed)");
}

TEST_F(ConnectTest, BadJsonNamesTheField) {
  const HttpResponse wrong_type =
      Post("RetimeCurves", "application/json", R"({"curves":{"frameCount":"many"}})");
  EXPECT_EQ(wrong_type.status, 400);
  EXPECT_EQ(ErrorOf(wrong_type).first, "invalid_argument");
  EXPECT_NE(ErrorOf(wrong_type).second.find("curves.frame_count"), std::string::npos)
      << ErrorOf(wrong_type).second;
  const HttpResponse unknown = Post("LipBlink", "application/json", R"({"mouthMood":1})");
  EXPECT_EQ(unknown.status, 400);
  EXPECT_NE(ErrorOf(unknown).second.find("mouthMood"), std::string::npos);
  const HttpResponse not_json = Post("RetimeSkeletal", "application/json", "{");
  EXPECT_EQ(not_json.status, 400);
  EXPECT_EQ(ErrorOf(not_json).first, "invalid_argument");
}

TEST_F(ConnectTest, ContentTypeVersionEncodingAndTimeout) {
  const HttpResponse text = Post("LipBlink", "text/plain", "x");
  EXPECT_EQ(text.status, 415);
  EXPECT_NE(ErrorOf(text).second.find("text/plain"), std::string::npos);
  EXPECT_EQ(*HeaderOf(text, "Accept-Post"), "application/json, application/proto");
  EXPECT_EQ(Post("LipBlink", "", "x").status, 415);
  // Parameters and case do not matter.
  std::string json;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(MakeLipBlinkRequest(), &json).ok());
  EXPECT_EQ(Post("LipBlink", "Application/JSON; charset=utf-8", json).status, 200);

  HttpRequest request;
  request.method = "POST";
  request.path = "/koma.v1.Retime/LipBlink";
  request.body = json;
  request.headers = {{"content-type", "application/json"}, {"connect-protocol-version", "2"}};
  HttpResponse response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 400);
  EXPECT_NE(ErrorOf(response).second.find("Connect-Protocol-Version"), std::string::npos);

  request.headers = {{"content-type", "application/json"}, {"content-encoding", "gzip"}};
  response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 501);
  EXPECT_EQ(ErrorOf(response).first, "unimplemented");

  request.headers = {{"content-type", "application/json"}, {"connect-timeout-ms", "soon"}};
  response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 400);
  EXPECT_NE(ErrorOf(response).second.find("Connect-Timeout-Ms: \"soon\""), std::string::npos);

  request.headers = {{"content-type", "application/json"},
                     {"connect-protocol-version", "1"},
                     {"connect-timeout-ms", "30000"},
                     {"x-request-id", "connect-test-1"}};
  response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 200) << response.body;
  ASSERT_NE(HeaderOf(response, "X-Request-Id"), nullptr);
  EXPECT_EQ(*HeaderOf(response, "X-Request-Id"), "connect-test-1");
}

TEST(ConnectTimeoutTest, ParsesPositiveWholeMillisecondsOfAtMostTenDigits) {
  EXPECT_EQ(server::ParseConnectTimeoutMs("1").value(), 1);
  EXPECT_EQ(server::ParseConnectTimeoutMs("9999999999").value(), 9999999999);
  for (const char* bad : {"", "0", "-5", "1.5", "12345678901", " 5", "5ms", "+5"}) {
    EXPECT_FALSE(server::ParseConnectTimeoutMs(bad).ok()) << bad;
  }
}

TEST_F(ConnectTest, UnknownMethodPathAndVerb) {
  const HttpResponse method = Post("RetimeEverything", "application/json", "{}");
  EXPECT_EQ(method.status, 404);
  EXPECT_EQ(ErrorOf(method).first, "not_found");
  EXPECT_NE(ErrorOf(method).second.find("/koma.v1.Retime/RetimeEverything"), std::string::npos);
  // LiveLipBlink is a stream: not on the HTTP port.
  EXPECT_EQ(Post("LiveLipBlink", "application/proto", "").status, 404);

  HttpRequest request;
  request.method = "GET";
  request.path = "/koma.v1.Retime/LipBlink";
  HttpResponse response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 405);
  EXPECT_EQ(*HeaderOf(response, "Allow"), "POST");
  for (const char* path : {"/etc/passwd", "/../../etc/passwd", "/koma.v1.Retime", "/metrics"}) {
    request.path = path;
    request.method = "POST";
    response = server_->http_server()->Respond(request);
    EXPECT_EQ(response.status, 404) << path;
    EXPECT_EQ(ErrorOf(response).first, "not_found") << path;
  }
}

TEST_F(ConnectTest, EveryResponseCarriesTheSecurityHeadersAndNoCors) {
  HttpRequest request;
  request.method = "POST";
  request.path = "/nowhere";
  request.headers = {{"origin", "https://evil.example"}};
  for (const HttpResponse& response :
       {server_->http_server()->Respond(request), PostJson("LipBlink", MakeLipBlinkRequest()),
        Post("LipBlink", "text/plain", "")}) {
    EXPECT_EQ(*HeaderOf(response, "Content-Security-Policy"),
              server::kDefaultContentSecurityPolicy);
    EXPECT_EQ(*HeaderOf(response, "X-Content-Type-Options"), "nosniff");
    EXPECT_EQ(*HeaderOf(response, "X-Frame-Options"), "DENY");
    EXPECT_EQ(*HeaderOf(response, "Referrer-Policy"), "no-referrer");
    EXPECT_EQ(HeaderOf(response, "Access-Control-Allow-Origin"), nullptr);
  }
  // No CORS configured: a preflight is not allowed.
  request.method = "OPTIONS";
  request.path = "/koma.v1.Retime/LipBlink";
  request.headers = {{"origin", "https://evil.example"},
                     {"access-control-request-method", "POST"}};
  const HttpResponse preflight = server_->http_server()->Respond(request);
  EXPECT_EQ(preflight.status, 405);
  EXPECT_EQ(HeaderOf(preflight, "Access-Control-Allow-Origin"), nullptr);
}

TEST_F(ConnectTest, AHandlersOwnPolicyReplacesTheDefault) {
  server_->http_server()->Handle("GET", "/page", [](const HttpRequest&) {
    HttpResponse response;
    response.SetHeader("Content-Security-Policy", "default-src 'self'");
    response.body = "page";
    return response;
  });
  HttpRequest request;
  request.method = "GET";
  request.path = "/page";
  const HttpResponse response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.body, "page");
  int policies = 0;
  for (const auto& [name, value] : response.headers) policies += name == "Content-Security-Policy";
  EXPECT_EQ(policies, 1);
  EXPECT_EQ(*HeaderOf(response, "Content-Security-Policy"), "default-src 'self'");
  EXPECT_EQ(HeaderOf(response, "X-Frame-Options"), nullptr);  // its frame-ancestors governs
  EXPECT_EQ(*HeaderOf(response, "X-Content-Type-Options"), "nosniff");
}

class ConnectCorsTest : public ConnectTest {
 protected:
  static server::ServerConfig CorsConfig() {
    server::ServerConfig config = Config();
    config.http.cors_origin = "https://tools.example.com";
    return config;
  }
  static void SetUpTestSuite() { Start(CorsConfig()); }
};

TEST_F(ConnectCorsTest, OnlyTheConfiguredOriginGetsCorsHeaders) {
  HttpRequest request;
  request.method = "OPTIONS";
  request.path = "/koma.v1.Retime/RetimeCurves";
  request.headers = {{"origin", "https://tools.example.com"},
                     {"access-control-request-method", "POST"}};
  HttpResponse response = server_->http_server()->Respond(request);
  EXPECT_EQ(response.status, 204);
  EXPECT_EQ(*HeaderOf(response, "Access-Control-Allow-Origin"), "https://tools.example.com");
  EXPECT_EQ(*HeaderOf(response, "Access-Control-Allow-Methods"), "POST");
  EXPECT_NE(HeaderOf(response, "Access-Control-Allow-Headers")->find("Connect-Timeout-Ms"),
            std::string::npos);

  request.headers[0].second = "https://evil.example";
  response = server_->http_server()->Respond(request);
  EXPECT_EQ(HeaderOf(response, "Access-Control-Allow-Origin"), nullptr);
}

TEST(ConnectCodesTest, EveryGrpcCodeHasConnectsNameAndHttpStatus) {
  // https://connectrpc.com/docs/protocol#error-codes
  const struct {
    grpc::StatusCode code;
    const char* name;
    int http;
  } table[] = {
      {grpc::StatusCode::CANCELLED, "canceled", 499},
      {grpc::StatusCode::UNKNOWN, "unknown", 500},
      {grpc::StatusCode::INVALID_ARGUMENT, "invalid_argument", 400},
      {grpc::StatusCode::DEADLINE_EXCEEDED, "deadline_exceeded", 504},
      {grpc::StatusCode::NOT_FOUND, "not_found", 404},
      {grpc::StatusCode::ALREADY_EXISTS, "already_exists", 409},
      {grpc::StatusCode::PERMISSION_DENIED, "permission_denied", 403},
      {grpc::StatusCode::RESOURCE_EXHAUSTED, "resource_exhausted", 429},
      {grpc::StatusCode::FAILED_PRECONDITION, "failed_precondition", 400},
      {grpc::StatusCode::ABORTED, "aborted", 409},
      {grpc::StatusCode::OUT_OF_RANGE, "out_of_range", 400},
      {grpc::StatusCode::UNIMPLEMENTED, "unimplemented", 501},
      {grpc::StatusCode::INTERNAL, "internal", 500},
      {grpc::StatusCode::UNAVAILABLE, "unavailable", 503},
      {grpc::StatusCode::DATA_LOSS, "data_loss", 500},
      {grpc::StatusCode::UNAUTHENTICATED, "unauthenticated", 401},
  };
  for (const auto& row : table) {
    EXPECT_EQ(server::ConnectCodeName(row.code), row.name);
    EXPECT_EQ(server::ConnectHttpStatus(row.code), row.http) << row.name;
    const HttpResponse error = server::ConnectError(row.code, "m \xff");
    EXPECT_EQ(error.status, row.http);
    EXPECT_EQ(error.body, std::string(R"({"code":")") + row.name + "\",\"message\":\"m \xEF\xBF\xBD\"}");
  }
}

TEST(HttpServerConfigTest, EachFlagOutOfRangeIsNamed) {
  const auto message = [](auto change) {
    server::HttpServerConfig config;
    config.port = 0;
    change(config);
    return std::string(server::ValidateHttpServerConfig(config).message());
  };
  EXPECT_EQ(message([](auto&) {}), "");
  EXPECT_EQ(message([](auto& c) { c.port = 70000; }).rfind("--http_port: 70000", 0), 0u);
  EXPECT_EQ(message([](auto& c) { c.address = "1.2.3.4,5.6.7.8"; }).rfind("--http_address", 0),
            0u);
  EXPECT_EQ(message([](auto& c) { c.max_body_bytes = 10; }).rfind("--http_max_body_bytes: 10", 0),
            0u);
  EXPECT_EQ(message([](auto& c) { c.request_timeout_ms = 5; })
                .rfind("--http_request_timeout_ms: 5", 0),
            0u);
  EXPECT_EQ(message([](auto& c) { c.threads = 0; }).rfind("--http_threads: 0", 0), 0u);
  EXPECT_EQ(message([](auto& c) { c.keep_alive_ms = -1; }).rfind("--http_keep_alive_ms: -1", 0),
            0u);
  EXPECT_EQ(message([](auto& c) { c.keep_alive_ms = 0; }), "");
  EXPECT_EQ(message([](auto& c) { c.cors_origin = "https://a.example/path"; })
                .rfind("--http_cors_origin", 0),
            0u);
  EXPECT_EQ(message([](auto& c) { c.cors_origin = "*"; }), "");
  EXPECT_EQ(message([](auto& c) { c.cors_origin = "http://localhost:8080"; }), "");
}

// The HTTP body counts against --max_memory_mb like a gRPC request: a JSON body whose parsed
// copies do not fit is refused resource_exhausted (429) naming the budget, before any parse.
class ConnectBudgetTest : public ConnectTest {
 protected:
  static server::ServerConfig BudgetConfig() {
    server::ServerConfig config = Config();
    config.max_memory_mb = 16;  // 8 MiB for calls
    return config;
  }
  static void SetUpTestSuite() { Start(BudgetConfig()); }
};

TEST_F(ConnectBudgetTest, ABodyOverTheBudgetIsRefused) {
  const std::string body(3 << 20, ' ');  // x3 for JSON: 9 MiB > 8 MiB
  const HttpResponse response = Post("RetimeCurves", "application/json", body);
  EXPECT_EQ(response.status, 429);
  EXPECT_EQ(ErrorOf(response).first, "resource_exhausted");
  EXPECT_NE(ErrorOf(response).second.find("--max_memory_mb=16"), std::string::npos)
      << ErrorOf(response).second;
  EXPECT_NE(ErrorOf(response).second.find("the HTTP request body"), std::string::npos);
  EXPECT_EQ(server_->memory_budget()->in_use(), 0);
  // A small call still fits, and its reservation is returned.
  EXPECT_EQ(PostJson("LipBlink", MakeLipBlinkRequest()).status, 200);
  EXPECT_EQ(server_->memory_budget()->in_use(), 0);
}

}  // namespace
}  // namespace koma::testing
