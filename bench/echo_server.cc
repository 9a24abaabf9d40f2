// koma_echo_server: the transport-only baseline for koma_load. It serves koma.v1.Retime
// with the same flags and message limits as koma_server but computes nothing: each RPC
// answers a response of the shape and size koma's would have for that request, so
// koma RPS / echo RPS shows what the retiming itself costs over the wire. LiveLipBlink too
// (bench/live_echo.h: one frame per grid frame, no analysis), for koma_live_load.
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/support/proto_buffer_writer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "absl/strings/str_cat.h"
#include "bench/echo_shapes.h"
#include "bench/live_echo.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/arena_allocator.h"
#include "platform/malloc_tuning.h"
#include "server/mutex_tuning.h"
#include "server/process_control.h"
#include "server/skeletal_parse.h"

ABSL_FLAG(std::string, address, "127.0.0.1:50052",
          "host:port to listen on; port 0 picks a free port (see --port_file)");
ABSL_FLAG(std::string, port_file, "",
          "if set, write the bound port number to this file once the server is serving");
ABSL_FLAG(int, max_message_bytes, 256 * 1024 * 1024, "largest request or response in bytes");
ABSL_FLAG(int64_t, huge_page_cache_mb, 0,
          "as koma_server's: MiB of released large-array memory kept for the next large call");

namespace {

// Answers like koma without computing (bench/echo_shapes.h). Messages live on per-call arenas,
// RetimeSkeletal is a raw method parsed by koma's own ParseSkeletalRequest, and malloc is tuned
// exactly as in koma_server, so the two differ only in the computing.
class EchoService final : public koma::v1::Retime::WithRawCallbackMethod_RetimeSkeletal<
                              koma::v1::Retime::CallbackService> {
 public:
  EchoService() {
    SetMessageAllocatorFor_RetimeCurves(&curves_messages_);
    SetMessageAllocatorFor_LipBlink(&lip_blink_messages_);
  }

 private:
  grpc::ServerUnaryReactor* RetimeSkeletal(grpc::CallbackServerContext* context,
                                           const grpc::ByteBuffer* request_bytes,
                                           grpc::ByteBuffer* response_bytes) override {
    // As koma_server's RetimeSkeletal (server/retime_service.cc): parse onto an arena, free the
    // received bytes, answer from an arena, serialise.
    auto request_arena =
        std::make_unique<google::protobuf::Arena>(koma::server::CallArenaOptions());
    auto* request = google::protobuf::Arena::CreateMessage<koma::v1::RetimeSkeletalRequest>(
        request_arena.get());
    const absl::Status parsed = koma::server::ParseSkeletalRequest(*request_bytes, request);
    const_cast<grpc::ByteBuffer*>(request_bytes)->Clear();
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    if (!parsed.ok()) {
      reactor->Finish(
          grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, std::string(parsed.message())));
      return reactor;
    }
    google::protobuf::Arena arena(koma::server::CallArenaOptions());
    using Response = koma::v1::RetimeSkeletalResponse;
    Response* response = google::protobuf::Arena::CreateMessage<Response>(&arena);
    koma::echo::SkeletalLookalike(*request, response);
    request_arena.reset();
    bool own_buffer = false;
    reactor->Finish(grpc::GenericSerialize<grpc::ProtoBufferWriter, Response>(
        *response, response_bytes, &own_buffer));
    return reactor;
  }

  grpc::ServerUnaryReactor* RetimeCurves(grpc::CallbackServerContext* context,
                                         const koma::v1::RetimeCurvesRequest* request,
                                         koma::v1::RetimeCurvesResponse* response) override {
    koma::echo::CurvesLookalike(*request, response);
    return Finish(context);
  }

  grpc::ServerUnaryReactor* LipBlink(grpc::CallbackServerContext* context,
                                     const koma::v1::LipBlinkRequest* request,
                                     koma::v1::LipBlinkResponse* response) override {
    koma::echo::LipBlinkLookalike(*request, response);
    return Finish(context);
  }

  grpc::ServerBidiReactor<koma::v1::LiveLipBlinkRequest, koma::v1::LiveLipBlinkFrame>*
  LiveLipBlink(grpc::CallbackServerContext* /*context*/) override {
    return koma::echo::OpenLiveEchoStream();
  }

  koma::server::ArenaMessageAllocator<koma::v1::RetimeCurvesRequest, koma::v1::RetimeCurvesResponse>
      curves_messages_;
  koma::server::ArenaMessageAllocator<koma::v1::LipBlinkRequest, koma::v1::LipBlinkResponse>
      lip_blink_messages_;

  static grpc::ServerUnaryReactor* Finish(grpc::CallbackServerContext* context) {
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    reactor->Finish(grpc::Status::OK);
    return reactor;
  }
};

int Fail(const std::string& message) {
  std::fprintf(stderr, "koma_echo_server: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  koma::platform::TuneMallocForLargeMessages();
  koma::server::IgnoreMutexDeadlockCycles();
  absl::SetProgramUsageMessage(
      "koma_echo_server [--address=HOST:PORT] [--port_file=F] [--max_message_bytes=N] "
      "[--huge_page_cache_mb=N]: "
      "koma.v1.Retime answering koma-sized responses without computing (load baseline)");
  absl::ParseCommandLine(argc, argv);
  koma::server::StopSignals stop_signals;  // as koma_server, before gRPC starts any thread

  const std::string address = absl::GetFlag(FLAGS_address);
  const int max_bytes = absl::GetFlag(FLAGS_max_message_bytes);
  if (max_bytes < 1024) return Fail("--max_message_bytes: below 1024");
  if (absl::GetFlag(FLAGS_huge_page_cache_mb) < 0) return Fail("--huge_page_cache_mb: negative");
  koma::platform::SetHugePageCache(absl::GetFlag(FLAGS_huge_page_cache_mb));
  EchoService service;
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(address, grpc::InsecureServerCredentials(), &port);
  builder.SetMaxReceiveMessageSize(max_bytes);
  builder.SetMaxSendMessageSize(max_bytes);
  builder.RegisterService(&service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (server == nullptr || port == 0) {
    return Fail(absl::StrCat("--address: could not listen on ", address));
  }
  server->GetHealthCheckService()->SetServingStatus(true);
  const std::string port_file = absl::GetFlag(FLAGS_port_file);
  if (!port_file.empty() && !koma::server::WritePortFile(port_file, port)) {
    return Fail(absl::StrCat("--port_file: cannot write ", port_file));
  }
  std::fprintf(stderr, "koma_echo_server listening on port %d\n", port);

  stop_signals.Wait();
  server->GetHealthCheckService()->SetServingStatus(false);
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(10));
  server->Wait();
  std::fprintf(stderr, "koma_echo_server stopped\n");
  return 0;
}
