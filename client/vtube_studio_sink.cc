#include "client/vtube_studio_sink.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace koma::client {
namespace {

// ErrorID.cs in github.com/DenchiSoft/VTubeStudio: the ones koma can cause or must explain.
constexpr int kApiAccessDeactivated = 1;
constexpr int kRequestRequiresAuthentication = 8;
constexpr int kTokenRequestDenied = 50;
constexpr int kTokenRequestOngoing = 51;
constexpr int kInjectParamNotFound = 453;
constexpr int kInjectParamControlledByOtherPlugin = 454;

// What the user can do about an errorID ("" when there is nothing to add).
std::string Hint(int error_id) {
  switch (error_id) {
    case kApiAccessDeactivated:
      return " (turn on \"Start API (allow plugins)\" in VTube Studio's settings)";
    case kRequestRequiresAuthentication:
      return " (the session is no longer authenticated: run koma live again)";
    case kTokenRequestDenied:
      return " (koma was denied: run koma live again and click Allow in VTube Studio's popup)";
    case kTokenRequestOngoing:
      return " (another popup for koma is open in VTube Studio: answer it first)";
    case kInjectParamNotFound:
      return " (VTube Studio has no input parameter of that name: check --vts-mouth-param, "
             "--vts-eye-left-param, --vts-eye-right-param)";
    case kInjectParamControlledByOtherPlugin:
      return " (another plugin is setting that parameter)";
    default:
      return "";
  }
}

std::string ErrorText(const VtsResponse& response) {
  return absl::StrCat("APIError ", response.error_id(), ": ", response.error_message(),
                      Hint(response.error_id()));
}

bool IsFatal(int error_id) {
  return error_id == kApiAccessDeactivated || error_id == kRequestRequiresAuthentication ||
         error_id == kTokenRequestDenied;
}

}  // namespace

std::string DefaultVtsTokenFile() {
  const char* config = std::getenv("XDG_CONFIG_HOME");
  if (config != nullptr && config[0] != '\0') return absl::StrCat(config, "/koma/vts-token");
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] != '\0') return absl::StrCat(home, "/.config/koma/vts-token");
  return "";
}

absl::StatusOr<std::string> ReadVtsToken(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (errno == ENOENT) return absl::NotFoundError(absl::StrCat("no token in ", path));
    return absl::PermissionDeniedError(
        absl::StrCat("cannot read ", path, ": ", std::strerror(errno)));
  }
  std::stringstream text;
  text << in.rdbuf();
  return std::string(absl::StripAsciiWhitespace(text.str()));
}

absl::Status WriteVtsToken(const std::string& path, const std::string& token) {
  std::error_code error;
  const std::filesystem::path file(path);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), error);
  if (error) {
    return absl::PermissionDeniedError(absl::StrCat(
        "cannot create ", file.parent_path().string(), ": ", error.message()));
  }
  const std::string temporary = absl::StrCat(path, ".tmp.", getpid());
  // 0600: the token lets any program on this machine control VTube Studio as koma.
  const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) {
    return absl::PermissionDeniedError(
        absl::StrCat("cannot write ", temporary, ": ", std::strerror(errno)));
  }
  const std::string contents = token + "\n";
  const bool written = write(fd, contents.data(), contents.size()) ==
                           static_cast<ssize_t>(contents.size()) &&
                       fsync(fd) == 0;
  const int saved_errno = errno;
  close(fd);
  if (!written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int code = written ? errno : saved_errno;
    std::remove(temporary.c_str());
    return absl::PermissionDeniedError(
        absl::StrCat("cannot write ", path, ": ", std::strerror(code)));
  }
  return absl::OkStatus();
}

std::vector<VtsParameterValue> VtsValuesOf(const v1::LiveLipBlinkFrame& frame,
                                           const AvatarLevels& levels, const VtsOptions& options) {
  const double eyes = EyeOpenness(frame, levels);
  return {
      {options.mouth_parameter, MouthOpenness(frame, levels)},
      {options.eye_left_parameter, eyes},
      {options.eye_right_parameter, eyes},
  };
}

VtubeStudioSink::VtubeStudioSink(VtsOptions options) : options_(std::move(options)) {
  if (options_.token_file.empty()) options_.token_file = DefaultVtsTokenFile();
}

VtubeStudioSink::~VtubeStudioSink() { (void)Close(); }

int64_t VtubeStudioSink::injects_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return injects_sent_;
}

absl::StatusOr<VtsResponse> VtubeStudioSink::Call(const std::string& request,
                                                  const std::string& request_id,
                                                  std::chrono::milliseconds timeout) {
  if (absl::Status sent = socket_->SendText(request); !sent.ok()) {
    return absl::UnavailableError(absl::StrCat("VTube Studio: ", sent.message()));
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    absl::StatusOr<std::string> text =
        socket_->Receive(std::max(left, std::chrono::milliseconds(0)));
    if (absl::IsDeadlineExceeded(text.status())) {
      return absl::DeadlineExceededError(
          absl::StrCat("VTube Studio did not answer within ", timeout.count() / 1000, " s"));
    }
    if (!text.ok()) {
      return absl::UnavailableError("VTube Studio closed the connection before answering");
    }
    absl::StatusOr<VtsResponse> response = ParseVtsResponse(*text);
    if (!response.ok()) return response.status();
    // Anything else (an event, a late answer) is not this call's answer.
    if (response->request_id == request_id) return response;
  }
}

absl::StatusOr<bool> VtubeStudioSink::AuthenticateWithToken(const std::string& token) {
  absl::StatusOr<VtsResponse> response =
      Call(VtsAuthenticationRequest(options_.plugin, token, "koma-authenticate"),
           "koma-authenticate", options_.reply_timeout);
  if (!response.ok()) return response.status();
  if (response->is_error()) {
    return absl::PermissionDeniedError(
        absl::StrCat("VTube Studio refused AuthenticationRequest: ", ErrorText(*response)));
  }
  if (response->message_type != "AuthenticationResponse") {
    return absl::InternalError(absl::StrCat("VTube Studio answered AuthenticationRequest with ",
                                            response->message_type));
  }
  const auto authenticated = response->data.find("authenticated");
  if (authenticated != response->data.end() && authenticated->is_boolean() &&
      authenticated->get<bool>()) {
    return true;
  }
  const auto reason = response->data.find("reason");
  std::fprintf(stderr, "koma: VTube Studio refused the saved token%s%s\n",
               reason != response->data.end() && reason->is_string() ? ": " : "",
               reason != response->data.end() && reason->is_string()
                   ? reason->get<std::string>().c_str()
                   : "");
  return false;
}

absl::Status VtubeStudioSink::Authenticate() {
  if (!options_.token_file.empty()) {
    absl::StatusOr<std::string> token = ReadVtsToken(options_.token_file);
    if (token.ok() && !token->empty()) {
      absl::StatusOr<bool> authenticated = AuthenticateWithToken(*token);
      if (!authenticated.ok()) return authenticated.status();
      if (*authenticated) return absl::OkStatus();
    } else if (!token.ok() && !absl::IsNotFound(token.status())) {
      return token.status();
    }
  }
  std::fprintf(stderr,
               "koma: VTube Studio: click \"Allow\" in its popup to let \"%s\" by \"%s\" set "
               "parameters (waiting up to %lld s)\n",
               options_.plugin.name.c_str(), options_.plugin.developer.c_str(),
               static_cast<long long>(options_.allow_timeout.count() / 1000));
  absl::StatusOr<VtsResponse> response =
      Call(VtsTokenRequest(options_.plugin, "koma-token"), "koma-token", options_.allow_timeout);
  if (!response.ok()) return response.status();
  if (response->is_error()) {
    return absl::PermissionDeniedError(
        absl::StrCat("VTube Studio refused AuthenticationTokenRequest: ", ErrorText(*response)));
  }
  const auto token = response->data.find("authenticationToken");
  if (response->message_type != "AuthenticationTokenResponse" ||
      token == response->data.end() || !token->is_string() ||
      token->get<std::string>().empty()) {
    return absl::InternalError(absl::StrCat("VTube Studio answered AuthenticationTokenRequest "
                                            "with ", response->message_type,
                                            " and no authenticationToken"));
  }
  if (options_.token_file.empty()) {
    std::fprintf(stderr, "koma: warning: neither XDG_CONFIG_HOME nor HOME is set: the token is "
                         "not saved (--vts-token-file)\n");
  } else if (absl::Status saved = WriteVtsToken(options_.token_file, token->get<std::string>());
             !saved.ok()) {
    std::fprintf(stderr, "koma: warning: --vts-token-file: %s (VTube Studio will ask again)\n",
                 std::string(saved.message()).c_str());
  }
  absl::StatusOr<bool> authenticated = AuthenticateWithToken(token->get<std::string>());
  if (!authenticated.ok()) return authenticated.status();
  if (!*authenticated) {
    return absl::PermissionDeniedError(
        "VTube Studio refused the token it had just issued (was koma's access revoked?)");
  }
  return absl::OkStatus();
}

absl::Status VtubeStudioSink::Start(const v1::LiveLipBlinkSetup& setup) {
  levels_ = AvatarLevelsOf(setup);
  absl::StatusOr<WebSocketUrl> url = ParseWebSocketUrl(options_.url);
  if (!url.ok()) return absl::InvalidArgumentError(absl::StrCat("--vts: ", url.status().message()));
  absl::StatusOr<std::unique_ptr<WebSocketClient>> socket = WebSocketClient::Connect(*url);
  if (!socket.ok()) {
    return absl::UnavailableError(absl::StrCat(
        "--vts: ", socket.status().message(),
        " (is VTube Studio running, with \"Start API (allow plugins)\" on, on this port?)"));
  }
  socket_ = std::move(*socket);
  if (absl::Status authenticated = Authenticate(); !authenticated.ok()) {
    socket_->Close();
    return absl::Status(authenticated.code(),
                        absl::StrCat("--vts: ", authenticated.message()));
  }
  resender_ = std::thread(&VtubeStudioSink::ResendLoop, this);
  return absl::OkStatus();
}

absl::Status VtubeStudioSink::SendValuesLocked(const std::string& id) {
  if (absl::Status sent = socket_->SendText(VtsInjectRequest(values_, id)); !sent.ok()) {
    failure_ = absl::UnavailableError("--vts: VTube Studio closed the connection");
    return failure_;
  }
  ++injects_sent_;
  last_sent_ = std::chrono::steady_clock::now();
  return absl::OkStatus();
}

void VtubeStudioSink::ReadAnswersLocked() {
  while (true) {
    absl::StatusOr<std::string> text = socket_->Receive(std::chrono::milliseconds(0));
    if (!text.ok()) {
      if (!absl::IsDeadlineExceeded(text.status()) && failure_.ok()) {
        failure_ = absl::UnavailableError("--vts: VTube Studio closed the connection");
      }
      return;
    }
    absl::StatusOr<VtsResponse> response = ParseVtsResponse(*text);
    if (!response.ok()) {
      if (errors_seen_[-1]++ == 0) {
        std::fprintf(stderr, "koma: warning: --vts: %s\n",
                     std::string(response.status().message()).c_str());
      }
      continue;
    }
    if (!response->is_error()) continue;
    const int id = response->error_id();
    if (IsFatal(id)) {  // the command prints it when the stream ends
      if (failure_.ok()) {
        failure_ = absl::PermissionDeniedError(
            absl::StrCat("--vts: VTube Studio: ", ErrorText(*response)));
      }
    } else if (errors_seen_[id]++ == 0) {  // once per errorID: each frame would repeat it
      std::fprintf(stderr, "koma: warning: --vts: VTube Studio: %s\n",
                   ErrorText(*response).c_str());
    }
  }
}

absl::Status VtubeStudioSink::Frame(const v1::LiveLipBlinkFrame& frame,
                                    const LiveFrameTiming& timing) {
  (void)timing;
  std::lock_guard<std::mutex> lock(mutex_);
  if (socket_ == nullptr) return absl::FailedPreconditionError("--vts: not started");
  ReadAnswersLocked();
  if (!failure_.ok()) {
    failure_returned_ = true;
    return failure_;
  }
  values_ = VtsValuesOf(frame, levels_, options_);
  // The request IDs tell a frame ("koma-frame-<grid frame>") from a re-send in VTube Studio's
  // log.
  absl::Status sent = SendValuesLocked(absl::StrCat("koma-frame-", frame.grid_frame()));
  failure_returned_ = !sent.ok();
  return sent;
}

void VtubeStudioSink::ResendLoop() {
  // Polls every 100 ms: reads answers, and re-sends the last values once they are
  // resend_after old (0.5 s: VTube Studio keeps an injected value about 1 s).
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, std::chrono::milliseconds(100));
    if (stop_) break;
    ReadAnswersLocked();
    if (!failure_.ok() || values_.empty()) continue;
    if (std::chrono::steady_clock::now() - last_sent_ >= options_.resend_after) {
      (void)SendValuesLocked(absl::StrCat("koma-resend-", ++resends_));
    }
  }
}

absl::Status VtubeStudioSink::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (resender_.joinable()) resender_.join();
  if (socket_ == nullptr) return absl::OkStatus();
  absl::Status result;
  {
    // The answers to the last frames: an APIError among them is still reported.
    std::lock_guard<std::mutex> lock(mutex_);
    if (!socket_->closed()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ReadAnswersLocked();
    // A failure Frame returned has been reported already; the connection closing after the
    // last frame lost nothing.
    if (!failure_.ok() && !failure_returned_ && !absl::IsUnavailable(failure_)) {
      result = failure_;
    }
  }
  socket_->Close();
  socket_.reset();
  return result;
}

}  // namespace koma::client
