// koma_server: the koma gRPC service. Flags are listed by --help.
#include <signal.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/reflection.h"
#include "absl/flags/usage.h"
#include "absl/flags/usage_config.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "koma/version.h"
#include "platform/huge_page_memory.h"
#include "platform/malloc_tuning.h"
#include "server/logging.h"
#include "server/mutex_tuning.h"
#include "server/page_routes.h"
#include "server/process_control.h"
#include "server/server.h"

ABSL_FLAG(std::string, address, "127.0.0.1:50051",
          "host:port to listen on; port 0 picks a free port (see --port_file); use "
          "0.0.0.0:50051 or [::]:50051 to accept remote clients");
ABSL_FLAG(std::string, port_file, "",
          "if set, write the bound port number to this file once the server is serving");
ABSL_FLAG(int, max_message_bytes, 256 * 1024 * 1024,
          "largest request or response in bytes (default 256 MiB: a 100k-frame, 31-joint "
          "clip is about 77 MB)");
ABSL_FLAG(int64_t, max_values, 20'000'000,
          "largest frames x values-per-frame in one request (values-per-frame = max(channels, "
          "3 x joints)); larger requests get RESOURCE_EXHAUSTED");
ABSL_FLAG(int, max_joints, 4096, "largest skeleton in joints");
ABSL_FLAG(int64_t, max_file_bytes, 64 * 1024 * 1024,
          "largest file a request may carry (bvh_text, gltf, motion3_json, csv_text) in bytes; "
          "larger files get RESOURCE_EXHAUSTED");
ABSL_FLAG(double, max_audio_seconds, 7200,
          "longest LipBlink recording (audio) in seconds, by its header and by its samples; "
          "longer ones get RESOURCE_EXHAUSTED");
ABSL_FLAG(int, max_audio_channels, 64,
          "most channels of a LipBlink recording (audio); more get RESOURCE_EXHAUSTED");
ABSL_FLAG(int64_t, max_audio_samples, 1'000'000'000,
          "most samples (sample frames x channels) one LipBlink recording may decode, by its "
          "header and by its samples; more get RESOURCE_EXHAUSTED");
ABSL_FLAG(int64_t, max_gltf_animations, 4096,
          "most animations a glTF file (RetimeSkeletalRequest.gltf) may have; more get "
          "RESOURCE_EXHAUSTED");
ABSL_FLAG(double, max_call_seconds, 300,
          "longest one call may compute, whatever its client's deadline; then its work stops "
          "and it is answered DEADLINE_EXCEEDED (0: no bound)");
ABSL_FLAG(int, live_max_streams, 1000,
          "LiveLipBlink streams at once; more are answered RESOURCE_EXHAUSTED");
ABSL_FLAG(double, live_max_seconds, 6 * 3600,
          "longest audio one LiveLipBlink stream may send, seconds; the stream then ends with "
          "RESOURCE_EXHAUSTED after its frames");
ABSL_FLAG(int64_t, live_max_message_bytes, 1 << 20,
          "largest LiveLipBlink audio message, bytes (gRPC's --max_message_bytes still applies)");
ABSL_FLAG(int, live_max_queued_frames, 240,
          "decided LiveLipBlink frames that may wait for a client that reads none; then the "
          "stream ends with RESOURCE_EXHAUSTED");
ABSL_FLAG(double, live_idle_seconds, 30,
          "longest a LiveLipBlink stream may go without a message, seconds (0: no bound); then "
          "it ends with DEADLINE_EXCEEDED");
ABSL_FLAG(int64_t, max_gltf_nodes, 65536,
          "most nodes a glTF file (RetimeSkeletalRequest.gltf) may have; more get "
          "INVALID_ARGUMENT naming nodes");
ABSL_FLAG(int, worker_threads, 0, "threads that run retiming; 0 = one per core");
ABSL_FLAG(int, threads_per_call, 0,
          "threads one large RetimeSkeletal call's forward kinematics may use (clips of 32768 "
          "frames and more); 0 = one per core, 1 = none besides the call's own");
ABSL_FLAG(int, max_queued, 64,
          "requests that may wait for a worker; beyond that, RESOURCE_EXHAUSTED (0: none wait, a "
          "large call runs only on an idle worker)");
ABSL_FLAG(int64_t, inline_max_bytes, koma::server::RetimeService::kDefaultInlineMaxBytes,
          "requests of at most this many bytes are retimed on gRPC's callback thread instead "
          "of a worker (saves two thread hand-offs on small clips); 0 = every request on a "
          "worker");
ABSL_FLAG(int64_t, huge_page_cache_mb, 0,
          "MiB of released large-array memory kept mapped for the next large call (faster large "
          "calls; resident memory may stay that much above what is in use); 0 = none");
ABSL_FLAG(int, idle_trim_ms, 1000,
          "once no call has run for this long (after large calls), give the memory they left "
          "in malloc's heap back to the system; 0 = never");
ABSL_FLAG(int64_t, max_memory_mb, -1,
          "memory all calls in flight may hold together, MiB; calls beyond it get "
          "RESOURCE_EXHAUSTED naming this budget. -1 = three quarters of the container's cgroup "
          "memory limit, or of the machine's memory without one; 0 = no budget");
ABSL_FLAG(std::string, log_level, "info", "trace, debug, info, warn, error, critical or off");
ABSL_FLAG(std::string, log_format, "text", "text, or json (one JSON object per line)");
ABSL_FLAG(std::string, tls_cert, "", "PEM certificate chain file: serve TLS instead of plaintext");
ABSL_FLAG(std::string, tls_key, "", "PEM private key file of --tls_cert");
ABSL_FLAG(std::string, tls_client_ca, "",
          "PEM CA file: require client certificates signed by it (mutual TLS)");
ABSL_FLAG(int, shutdown_delay_ms, 1000,
          "on SIGTERM/SIGINT, how long health reports NOT_SERVING while calls are still "
          "accepted, so clients and load balancers that watch health move away first");
ABSL_FLAG(int, shutdown_grace_ms, 10000,
          "on SIGTERM/SIGINT, after --shutdown_delay_ms, how long calls in flight may finish "
          "before they are cancelled; the process exits at the latest 0.2 s after it, whatever "
          "is still computing");
ABSL_FLAG(std::string, metrics_address, "",
          "host:port for Prometheus metrics (plain HTTP GET /metrics); port 0 picks a free port "
          "(see --metrics_port_file); empty = no metrics. Use 0.0.0.0:9464 in a container");
ABSL_FLAG(std::string, metrics_port_file, "",
          "if set, write the bound metrics port number to this file once serving (before "
          "--port_file is written)");
ABSL_FLAG(int, http_port, -1,
          "port of the HTTP server (the page and the Connect JSON API, POST "
          "/koma.v1.Retime/<Method>); -1 = none, 0 = a free port (see --http_port_file)");
ABSL_FLAG(std::string, http_address, "127.0.0.1",
          "address the HTTP port listens on; loopback by default, 0.0.0.0 to accept remote "
          "browsers (in a container)");
ABSL_FLAG(std::string, http_port_file, "",
          "if set, write the bound HTTP port number to this file once serving (before "
          "--port_file is written)");
ABSL_FLAG(int64_t, http_max_body_bytes, 64 * 1024 * 1024,
          "largest HTTP request body, bytes; larger ones are answered 413 unread");
ABSL_FLAG(int, http_request_timeout_ms, 30000,
          "longest the HTTP port waits for a request's headers and body, milliseconds; a "
          "slower client gets 408 and the connection is closed");
ABSL_FLAG(int, http_threads, 8,
          "HTTP connections served at once (each holds a thread while its request arrives and "
          "its call runs, and while kept alive idle); more wait for a thread");
ABSL_FLAG(int, http_keep_alive_ms, 1000,
          "how long an HTTP connection may stay open idle for its next request, milliseconds; "
          "0 = one request per connection");
ABSL_FLAG(std::string, http_cors_origin, "",
          "the one origin (https://host[:port], or *) whose pages may call the HTTP port from a "
          "browser; empty = no CORS headers (same-origin only)");

namespace {

// clang-format off
constexpr const char* kEnvironmentFlags[] = {
    "address",             "port_file",           "max_message_bytes",   "max_values",
    "max_joints",          "worker_threads",      "max_queued",          "log_level",
    "log_format",          "shutdown_grace_ms",   "tls_cert",            "tls_key",
    "tls_client_ca",       "metrics_address",     "metrics_port_file",   "shutdown_delay_ms",
    "inline_max_bytes",    "huge_page_cache_mb",  "threads_per_call",    "idle_trim_ms",
    "max_memory_mb",       "max_file_bytes",      "max_gltf_nodes",      "max_audio_seconds",
    "max_audio_channels",  "max_audio_samples",   "max_gltf_animations", "max_call_seconds",
    "live_max_streams",    "live_max_seconds",    "live_max_message_bytes",
    "live_max_queued_frames",                     "live_idle_seconds",
    "http_port",           "http_address",        "http_port_file",      "http_max_body_bytes",
    "http_request_timeout_ms",                    "http_threads",        "http_cors_origin",
    "http_keep_alive_ms"};
// clang-format on

// Each flag may also come from the environment as KOMA_<FLAG> (KOMA_ADDRESS,
// KOMA_LOG_FORMAT, ...), for containers; a flag on the command line wins. False (with a
// message) when a variable's value does not parse.
bool ApplyEnvironment() {
  for (const char* name : kEnvironmentFlags) {
    const std::string variable = "KOMA_" + absl::AsciiStrToUpper(name);
    const char* value = std::getenv(variable.c_str());
    if (value == nullptr) continue;
    absl::CommandLineFlag* flag = absl::FindCommandLineFlag(name);
    std::string error;
    if (flag == nullptr || !flag->ParseFrom(value, &error)) {
      std::fprintf(stderr, "koma_server: %s=\"%s\": %s\n", variable.c_str(), value, error.c_str());
      return false;
    }
  }
  return true;
}

// The whole file, or false with a message naming the flag.
bool ReadPem(const char* flag, const std::string& path, std::string* out) {
  if (path.empty()) return true;
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || text.str().empty()) {
    std::fprintf(stderr, "koma_server: --%s: cannot read %s\n", flag, path.c_str());
    return false;
  }
  *out = text.str();
  return true;
}

bool ReadTls(koma::server::ServerConfig& config) {
  return ReadPem("tls_cert", absl::GetFlag(FLAGS_tls_cert), &config.tls_cert_pem) &&
         ReadPem("tls_key", absl::GetFlag(FLAGS_tls_key), &config.tls_key_pem) &&
         ReadPem("tls_client_ca", absl::GetFlag(FLAGS_tls_client_ca), &config.tls_client_ca_pem);
}

koma::server::ServerConfig ConfigFromFlags() {
  koma::server::ServerConfig config;
  config.address = absl::GetFlag(FLAGS_address);
  config.max_message_bytes = absl::GetFlag(FLAGS_max_message_bytes);
  config.limits.max_values = absl::GetFlag(FLAGS_max_values);
  config.limits.max_joints = absl::GetFlag(FLAGS_max_joints);
  config.limits.max_file_bytes = absl::GetFlag(FLAGS_max_file_bytes);
  config.limits.max_audio_seconds = absl::GetFlag(FLAGS_max_audio_seconds);
  config.limits.max_audio_channels = absl::GetFlag(FLAGS_max_audio_channels);
  config.limits.max_gltf_nodes = absl::GetFlag(FLAGS_max_gltf_nodes);
  config.limits.max_audio_samples = absl::GetFlag(FLAGS_max_audio_samples);
  config.limits.max_gltf_animations = absl::GetFlag(FLAGS_max_gltf_animations);
  config.limits.max_call_seconds = absl::GetFlag(FLAGS_max_call_seconds);
  config.limits.live_max_streams = absl::GetFlag(FLAGS_live_max_streams);
  config.limits.live_max_seconds = absl::GetFlag(FLAGS_live_max_seconds);
  config.limits.live_max_message_bytes = absl::GetFlag(FLAGS_live_max_message_bytes);
  config.limits.live_max_queued_frames = absl::GetFlag(FLAGS_live_max_queued_frames);
  config.limits.live_idle_seconds = absl::GetFlag(FLAGS_live_idle_seconds);
  const int threads_per_call = absl::GetFlag(FLAGS_threads_per_call);
  config.limits.threads_per_call =
      threads_per_call > 0 ? threads_per_call
                           : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  config.worker_threads = absl::GetFlag(FLAGS_worker_threads);
  config.max_queued = absl::GetFlag(FLAGS_max_queued);
  config.inline_max_bytes = absl::GetFlag(FLAGS_inline_max_bytes);
  config.idle_trim = absl::Milliseconds(absl::GetFlag(FLAGS_idle_trim_ms));
  config.metrics_address = absl::GetFlag(FLAGS_metrics_address);
  config.http.port = absl::GetFlag(FLAGS_http_port);
  config.http.address = absl::GetFlag(FLAGS_http_address);
  config.http.max_body_bytes = absl::GetFlag(FLAGS_http_max_body_bytes);
  config.http.request_timeout_ms = absl::GetFlag(FLAGS_http_request_timeout_ms);
  config.http.threads = absl::GetFlag(FLAGS_http_threads);
  config.http.keep_alive_ms = absl::GetFlag(FLAGS_http_keep_alive_ms);
  config.http.cors_origin = absl::GetFlag(FLAGS_http_cors_origin);
  const int64_t max_memory_mb = absl::GetFlag(FLAGS_max_memory_mb);
  config.max_memory_mb =
      max_memory_mb == -1 ? koma::server::DefaultMemoryBudgetMb() : max_memory_mb;
  return config;
}

// The --address with its port replaced by the bound one ("127.0.0.1:0" -> "127.0.0.1:41149").
std::string ListeningAddress(const std::string& address, int port) {
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) return absl::StrCat(address, " (port ", port, ")");
  return absl::StrCat(address.substr(0, colon + 1), port);
}

// The flags that main() applies itself (the rest go through KomaServer::Start's checks):
// "--flag: value must be ..." for the first one out of range, else empty.
std::string ProcessFlagError() {
  const struct {
    const char* flag;
    int64_t value;
    const char* meaning_of_zero;
  } kAtLeastZero[] = {
      {"huge_page_cache_mb", absl::GetFlag(FLAGS_huge_page_cache_mb), "none kept"},
      {"threads_per_call", absl::GetFlag(FLAGS_threads_per_call), "one per core"},
      {"shutdown_delay_ms", absl::GetFlag(FLAGS_shutdown_delay_ms),
       "NOT_SERVING, then drain at once"},
      {"shutdown_grace_ms", absl::GetFlag(FLAGS_shutdown_grace_ms),
       "cancel calls in flight at once"},
  };
  for (const auto& setting : kAtLeastZero) {
    if (setting.value < 0) {
      return absl::StrCat("--", setting.flag, ": ", setting.value,
                          " must be >= 0 (0 = ", setting.meaning_of_zero, ")");
    }
  }
  return "";
}

int Fail(const std::string& message) {
  std::fprintf(stderr, "koma_server: %s\n", message.c_str());
  return 1;
}

// The grace is a promise to whoever sent the signal (an orchestrator's termination grace, a
// rolling restart): gRPC cancels the calls still in flight when it ends, but a handler whose
// work has no cancellation point keeps its worker, and the drain would wait for it. So the
// process exits kExitMargin after the grace whatever is still computing (a stateless server
// loses nothing the cancelled calls had not lost already).
constexpr absl::Duration kExitMargin = absl::Milliseconds(200);
void ExitAfterTheGrace(absl::Duration grace) {
  std::thread([grace] {
    absl::SleepFor(grace + kExitMargin);
    koma::server::LogEvent(
        "calls still computing after the grace were cancelled; exiting without them", true);
    std::fflush(stderr);
    std::_Exit(0);
  }).detach();
}

}  // namespace

int main(int argc, char** argv) {
  koma::platform::TuneMallocForLargeMessages();
  koma::platform::UseHugePagesForLargeArrays();
  koma::server::IgnoreMutexDeadlockCycles();
  absl::FlagsUsageConfig usage;
  // --help lists this file's flags (Abseil's default looks for a file named after the binary).
  usage.contains_help_flags = [](absl::string_view file) {
    return absl::EndsWith(file, "server/main.cc");
  };
  usage.contains_helpshort_flags = usage.contains_help_flags;
  // --version: Abseil's default prints the program name and "Debug build (NDEBUG not
  // #defined)" (Debian's Abseil is built without NDEBUG), whatever this build is.
  usage.version_string = [] { return std::string("koma_server ") + koma::kVersion + "\n"; };
  absl::SetFlagsUsageConfig(usage);
  absl::SetProgramUsageMessage(
      "koma_server [--address=HOST:PORT] [flags]: the koma gRPC service. Every flag can also be "
      "set as KOMA_<FLAG> in the environment (KOMA_ADDRESS=0.0.0.0:50051); flags win.");
  if (!ApplyEnvironment()) return 1;  // as for a bad flag on the command line (Abseil exits 1)
  absl::ParseCommandLine(argc, argv);
  if (absl::Status s = koma::server::ConfigureLogging(absl::GetFlag(FLAGS_log_level),
                                                      absl::GetFlag(FLAGS_log_format));
      !s.ok()) {
    return Fail(std::string(s.message()));
  }
  koma::server::StopSignals stop_signals;  // before gRPC starts any thread
  if (std::string error = ProcessFlagError(); !error.empty()) return Fail(error);
  koma::platform::SetHugePageCache(absl::GetFlag(FLAGS_huge_page_cache_mb));

  koma::server::ServerConfig config = ConfigFromFlags();
  if (!ReadTls(config)) return 1;
  const std::string metrics_port_file = absl::GetFlag(FLAGS_metrics_port_file);
  if (!metrics_port_file.empty() && config.metrics_address.empty()) {
    return Fail("--metrics_port_file needs --metrics_address");
  }
  auto server = koma::server::KomaServer::Start(config);
  if (!server.ok()) return Fail(std::string(server.status().message()));
  // The page (server/page_routes.h) beside the Connect API, before any port file is written.
  if (koma::server::HttpServer* http = (*server)->http_server()) {
    koma::server::RegisterPageRoutes(*http, (*server)->InProcessChannel());
  }
  const std::string http_port_file = absl::GetFlag(FLAGS_http_port_file);
  if (!http_port_file.empty() && config.http.port == -1) {
    return Fail("--http_port_file needs --http_port");
  }
  if (!http_port_file.empty() &&
      !koma::server::WritePortFile(http_port_file, (*server)->http_port())) {
    return Fail(absl::StrCat("--http_port_file: cannot write ", http_port_file));
  }
  // Before --port_file: a script that waits for the port file finds both.
  if (!metrics_port_file.empty() &&
      !koma::server::WritePortFile(metrics_port_file, (*server)->metrics_port())) {
    return Fail(absl::StrCat("--metrics_port_file: cannot write ", metrics_port_file));
  }
  const std::string port_file = absl::GetFlag(FLAGS_port_file);
  if (!port_file.empty() && !koma::server::WritePortFile(port_file, (*server)->port())) {
    return Fail(absl::StrCat("--port_file: cannot write ", port_file));
  }
  const char* security = config.tls_cert_pem.empty()        ? "plaintext"
                         : config.tls_client_ca_pem.empty() ? "TLS"
                                                            : "mutual TLS";
  koma::server::LogEvent(absl::StrCat(
      "koma_server listening on ",
      ListeningAddress(absl::GetFlag(FLAGS_address), (*server)->port()), " (", security, ")"));
  if (!config.metrics_address.empty()) {
    koma::server::LogEvent(absl::StrCat(
        "metrics on http://", ListeningAddress(config.metrics_address, (*server)->metrics_port()),
        "/metrics"));
  }

  if (config.http.port != -1) {
    koma::server::LogEvent(absl::StrCat("HTTP (the page, the Connect JSON API) on http://",
                                        config.http.address, ":", (*server)->http_port(), "/"));
  }

  const int signal_number = stop_signals.Wait();
  const int delay_ms = absl::GetFlag(FLAGS_shutdown_delay_ms);  // >= 0 (ProcessFlagError)
  koma::server::LogEvent(absl::StrCat("received ", signal_number == SIGTERM ? "SIGTERM" : "SIGINT",
                                      ", NOT_SERVING; still accepting calls for ", delay_ms,
                                      " ms"));
  // Calls that reach a gRPC server after its Shutdown began are cancelled, so the clients
  // that watch health (koma's own with a server list) get time to move away first.
  (*server)->StopServing();
  absl::SleepFor(absl::Milliseconds(delay_ms));
  const int grace_ms = absl::GetFlag(FLAGS_shutdown_grace_ms);
  koma::server::LogEvent(absl::StrCat("draining (grace ", grace_ms, " ms)"));
  ExitAfterTheGrace(absl::Milliseconds(grace_ms));
  (*server)->Shutdown(absl::Milliseconds(grace_ms));
  koma::server::LogEvent("koma_server stopped");
  return 0;
}
