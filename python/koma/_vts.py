"""Live frames into VTube Studio through its public plugin API (JSON over a WebSocket,
ws://localhost:8001 by default), as the C++ `koma live --vts` (client/vtube_studio_sink.cc,
client/vts_messages.cc; docs/live.md, "VTube Studio").

start() connects and authenticates: with the token saved by an earlier run (token_file) an
AuthenticationRequest is enough; without one, or when VTube Studio refuses it, an
AuthenticationTokenRequest makes VTube Studio ask the user to allow "koma", and the token it
answers is saved (0600). Then every frame is one InjectParameterDataRequest ("koma-frame-<grid
frame>", faceFound false, mode "set") of MouthOpen, EyeOpenLeft and EyeOpenRight (0..1, the
setup's levels mapped as for VMC); the last values are sent again ("koma-resend-N") every
0.5 s while no frame comes, as VTube Studio forgets an injected value after about 1 s.

Debian 12's python3-websockets (10.4) has only the asyncio API, so the connection lives on an
event loop in a thread of its own; websockets is imported only here, only with --vts.
"""
import asyncio
import json
import os
import sys
import threading
import time

from koma._vmc import _normalised

DEFAULT_URL = "ws://localhost:8001"
PLUGIN_NAME = "koma"
PLUGIN_DEVELOPER = "koma contributors"
API_NAME = "VTubeStudioPublicAPI"

# ErrorID.cs in github.com/DenchiSoft/VTubeStudio: the ones koma can cause or must explain.
API_ACCESS_DEACTIVATED = 1
REQUEST_REQUIRES_AUTHENTICATION = 8
TOKEN_REQUEST_DENIED = 50
TOKEN_REQUEST_ONGOING = 51
INJECT_PARAM_NOT_FOUND = 453
INJECT_PARAM_CONTROLLED_BY_OTHER_PLUGIN = 454
_HINTS = {
    API_ACCESS_DEACTIVATED:
        " (turn on \"Start API (allow plugins)\" in VTube Studio's settings)",
    REQUEST_REQUIRES_AUTHENTICATION:
        " (the session is no longer authenticated: run koma live again)",
    TOKEN_REQUEST_DENIED:
        " (koma was denied: run koma live again and click Allow in VTube Studio's popup)",
    TOKEN_REQUEST_ONGOING:
        " (another popup for koma is open in VTube Studio: answer it first)",
    INJECT_PARAM_NOT_FOUND:
        " (VTube Studio has no input parameter of that name: check --vts-mouth-param, "
        "--vts-eye-left-param, --vts-eye-right-param)",
    INJECT_PARAM_CONTROLLED_BY_OTHER_PLUGIN: " (another plugin is setting that parameter)",
}
_FATAL = (API_ACCESS_DEACTIVATED, REQUEST_REQUIRES_AUTHENTICATION, TOKEN_REQUEST_DENIED)
_ASCII_SPACE = " \t\n\v\f\r"


class VtsError(Exception):
    """Ends the command with exit status 1 ("koma: <message>"). closed: VTube Studio closed
    the connection (nothing lost when that comes after the last frame)."""

    def __init__(self, message, closed=False):
        super().__init__(message)
        self.closed = closed


def parse_url(url):
    """"ws://HOST[:PORT][/PATH]" (port 80 when absent, path "/") or "HOST:PORT" -> (host, port,
    path), as the C++ ParseWebSocketUrl; ValueError naming the URL otherwise (wss:// too)."""
    rest = url
    if rest.lower().startswith("wss://"):
        raise ValueError(f"\"{url}\": wss:// (TLS) is not supported; use ws://")
    has_scheme = rest.lower().startswith("ws://")
    if has_scheme:
        rest = rest[5:]
    path = "/"
    slash = rest.find("/")
    if slash >= 0:
        rest, path = rest[:slash], rest[slash:]
    port, port_given = "", False
    if rest.startswith("["):  # [IPv6]
        close = rest.find("]")
        if close < 0:
            raise ValueError(f"\"{url}\": unclosed [ in the host")
        host = rest[1:close]
        if close + 1 < len(rest):
            if rest[close + 1] != ":":
                raise ValueError(f"\"{url}\": bad host")
            port, port_given = rest[close + 2:], True
    else:
        host, colon, after = rest.partition(":")
        if colon:
            port, port_given = after, True
    if not host:
        raise ValueError(f"\"{url}\" has no host (ws://localhost:8001)")
    if not port and (not has_scheme or port_given):
        raise ValueError(f"\"{url}\" must be ws://HOST:PORT or HOST:PORT (ws://localhost:8001)")
    if port and not (port.isascii() and port.isdigit() and 1 <= int(port) <= 65535):
        raise ValueError(f"\"{url}\": port \"{port}\" must be a number in [1, 65535]")
    return host, int(port) if port else 80, path


def default_token_file():
    """$XDG_CONFIG_HOME/koma/vts-token, else $HOME/.config/koma/vts-token; "" when neither is
    set."""
    config = os.environ.get("XDG_CONFIG_HOME", "")
    if config:
        return f"{config}/koma/vts-token"
    home = os.environ.get("HOME", "")
    if home:
        return f"{home}/.config/koma/vts-token"
    return ""


def read_token(path):
    """The saved token (surrounding white space removed); None when the file does not exist."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        return None
    except OSError as error:
        raise VtsError(f"cannot read {path}: {error.strerror or error}") from None
    return data.decode("utf-8", "replace").strip(_ASCII_SPACE)


def write_token(path, token):
    """Saves the token readable by its owner only (0600), creating the folders, replacing the
    file atomically (a rename). OSError with the C++ client's words."""
    parent = os.path.dirname(path)
    if parent:
        try:
            os.makedirs(parent, exist_ok=True)
        except OSError as error:
            raise OSError(f"cannot create {parent}: {error.strerror or error}") from None
    temporary = f"{path}.tmp.{os.getpid()}"
    try:
        # 0600: the token lets any program on this machine control VTube Studio as koma.
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_CLOEXEC, 0o600)
    except OSError as error:
        raise OSError(f"cannot write {temporary}: {error.strerror or error}") from None
    try:
        try:
            os.write(fd, (token + "\n").encode())
            os.fsync(fd)
        finally:
            os.close(fd)
        os.rename(temporary, path)
    except OSError as error:
        try:
            os.remove(temporary)
        except OSError:
            pass
        raise OSError(f"cannot write {path}: {error.strerror or error}") from None


def request(message_type, request_id, data):
    """A request's JSON text, as the C++ client writes it (nlohmann::json: keys sorted, no
    spaces)."""
    return json.dumps({"apiName": API_NAME, "apiVersion": "1.0", "requestID": request_id,
                       "messageType": message_type, "data": data},
                      sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def token_request(request_id):
    return request("AuthenticationTokenRequest", request_id,
                   {"pluginName": PLUGIN_NAME, "pluginDeveloper": PLUGIN_DEVELOPER})


def authentication_request(token, request_id):
    return request("AuthenticationRequest", request_id,
                   {"pluginName": PLUGIN_NAME, "pluginDeveloper": PLUGIN_DEVELOPER,
                    "authenticationToken": token})


def inject_request(values, request_id):
    """InjectParameterDataRequest of [(id, value), ...], faceFound false, mode "set"."""
    return request("InjectParameterDataRequest", request_id,
                   {"faceFound": False, "mode": "set",
                    "parameterValues": [{"id": i, "value": float(v)} for i, v in values]})


def parse_response(text):
    """(messageType, requestID, data) of an answer; ValueError as the C++ ParseVtsResponse."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    try:
        message = json.loads(text)
    except ValueError:
        message = None
    if not isinstance(message, dict):
        raise ValueError("VTube Studio answered with something that is not a JSON object: "
                         f"{text[:200]}")
    message_type = message.get("messageType")
    if not isinstance(message_type, str):
        raise ValueError(f"VTube Studio answered without a messageType: {text[:200]}")
    request_id = message.get("requestID")
    data = message.get("data")
    if data is None:
        data = {}
    elif not isinstance(data, dict):
        raise ValueError(f"VTube Studio's {message_type} has a data that is not an object")
    return message_type, request_id if isinstance(request_id, str) else "", data


def _error_id(data):
    value = data.get("errorID")
    return value if isinstance(value, int) and not isinstance(value, bool) else -1


def _error_text(data):
    message = data.get("message")
    error_id = _error_id(data)
    return (f"APIError {error_id}: {message if isinstance(message, str) else ''}"
            f"{_HINTS.get(error_id, '')}")


def _warn(text):
    sys.stderr.write(f"koma: {text}\n")
    sys.stderr.flush()


class VtsSender:
    """Injects each frame's mouth and eyes into VTube Studio at url: start() before the
    stream, send(frame) per frame, close() after. The levels are mapped from mouth_range and
    eye_range (koma._vmc.levels()) to 0..1."""

    def __init__(self, url=DEFAULT_URL, token_file=None, mouth_range=(0.0, 1.0),
                 eye_range=(0.0, 1.0), mouth_param="MouthOpen", eye_left_param="EyeOpenLeft",
                 eye_right_param="EyeOpenRight", allow_timeout=120.0, reply_timeout=10.0,
                 resend_after=0.5):
        for flag, name in (("--vts-mouth-param", mouth_param),
                           ("--vts-eye-left-param", eye_left_param),
                           ("--vts-eye-right-param", eye_right_param)):
            if not name:
                raise ValueError(f"{flag} must not be empty")
        self.url = url or DEFAULT_URL
        try:
            self.host, self.port, self.path = parse_url(self.url)
        except ValueError as error:
            raise ValueError(f"--vts: {error}") from None
        try:
            import websockets.client  # noqa: PLC0415  (only with --vts)
            import websockets.exceptions  # noqa: PLC0415
        except ImportError:
            raise ImportError("--vts needs the websockets Python module: install the Debian "
                              "package python3-websockets (apt-get install "
                              "python3-websockets)") from None
        self._websockets = websockets
        self.token_file = default_token_file() if not token_file else token_file
        self.mouth_range, self.eye_range = mouth_range, eye_range
        self.params = (mouth_param, eye_left_param, eye_right_param)
        self.allow_timeout, self.reply_timeout = allow_timeout, reply_timeout
        self.resend_after = resend_after
        self.injects_sent = 0
        self.resends = 0
        self._socket = None
        self._loop = None
        self._thread = None
        self._tasks = []
        self._values = None  # the last frame's; None before the first
        self._last_sent = 0.0
        self._errors_seen = {}  # errorID -> count of APIError answers
        self._failure = None  # a VtsError once the stream must end
        self._failure_returned = False

    # The synchronous side (the caller's thread).

    def _run(self, coroutine, timeout=None):
        future = asyncio.run_coroutine_threadsafe(coroutine, self._loop)
        try:
            return future.result(timeout)
        except BaseException:
            future.cancel()  # Ctrl-C while waiting for the popup, a timeout
            raise

    def values(self, frame):
        """The frame's [(parameter, value)]: mouth, left eye, right eye (one blink timing)."""
        eyes = _normalised(frame.eye_level, self.eye_range)
        return [(self.params[0], _normalised(frame.mouth_level, self.mouth_range)),
                (self.params[1], eyes), (self.params[2], eyes)]

    def start(self):
        """Connects and authenticates; VtsError ("--vts: ...") naming what the user can do."""
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name="koma-vts",
                                        daemon=True)
        self._thread.start()
        try:
            self._run(self._start())
        except BaseException:
            self._shutdown()
            raise

    def send(self, frame):
        """Sends the frame's values without waiting for the answer. VtsError when the stream
        must end (access revoked or the API turned off, the connection closed)."""
        if self._loop is None:
            raise VtsError("--vts: not started")
        self._run(self._frame(self.values(frame), f"koma-frame-{frame.grid_frame}"))

    def close(self):
        """Stops the re-sending, reads the last answers, closes the connection. Returns a
        VtsError to report (one send() has not raised already), else None."""
        if self._loop is None:
            return None
        try:
            return self._run(self._close(), timeout=15)
        except Exception:  # noqa: BLE001  (closing: nothing more to report)
            return None
        finally:
            self._shutdown()

    def _shutdown(self):
        loop, self._loop = self._loop, None
        if loop is None:
            return
        try:
            asyncio.run_coroutine_threadsafe(self._cancel_all(), loop).result(5)
        except BaseException:  # noqa: BLE001  (closing anyway)
            pass
        loop.call_soon_threadsafe(loop.stop)
        self._thread.join(5)
        if not self._thread.is_alive():
            loop.close()

    # The event loop's side: everything below runs on self._loop's thread.

    async def _cancel_all(self):
        """Ends the tasks still running and the connection, so the loop stops clean (a _run
        cancelled has cancelled its own; websockets' tasks end with the connection)."""
        for task in self._tasks:
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
        await asyncio.sleep(0)
        if self._socket is not None and not getattr(self._socket, "closed", False):
            await self._socket.close()

    async def _start(self):
        websockets = self._websockets
        host = f"[{self.host}]" if ":" in self.host else self.host
        url = f"ws://{host}:{self.port}{self.path}"
        try:
            # As the C++ client (civetweb): no compression, no pings, no Origin.
            self._socket = await websockets.client.connect(
                url, compression=None, ping_interval=None, open_timeout=self.reply_timeout,
                close_timeout=2, max_size=None)
        except Exception as error:  # noqa: BLE001  (OSError, InvalidHandshake, timeout)
            errno = getattr(error, "errno", None)
            why = (os.strerror(errno) if isinstance(errno, int) and errno > 0 else
                   getattr(error, "strerror", None)) or str(error) or type(error).__name__
            if isinstance(error, asyncio.TimeoutError):
                why = f"no WebSocket handshake within {int(self.reply_timeout)} s"
            raise VtsError(f"--vts: cannot open {url}: {why} (is VTube Studio running, with "
                           "\"Start API (allow plugins)\" on, on this port?)") from None
        try:
            await self._authenticate()
        except VtsError as error:
            await self._socket.close()
            raise VtsError(f"--vts: {error}") from None
        self._tasks = [asyncio.ensure_future(self._read_answers()),
                       asyncio.ensure_future(self._resend_loop())]

    async def _call(self, text, request_id, timeout):
        """Sends a request and waits for its answer: (messageType, data)."""
        closed = self._websockets.exceptions.ConnectionClosed
        try:
            await self._socket.send(text)
        except closed as error:
            raise VtsError(f"VTube Studio: {error}") from None
        deadline = time.monotonic() + timeout
        while True:
            try:
                answer = await asyncio.wait_for(self._socket.recv(),
                                                max(0.0, deadline - time.monotonic()))
            except asyncio.TimeoutError:
                raise VtsError(f"VTube Studio did not answer within {int(timeout)} s") from None
            except closed:
                raise VtsError("VTube Studio closed the connection before answering") from None
            try:
                message_type, answer_id, data = parse_response(answer)
            except ValueError as error:
                raise VtsError(str(error)) from None
            # Anything else (an event, a late answer) is not this call's answer.
            if answer_id == request_id:
                return message_type, data

    async def _authenticate_with(self, token):
        """True when VTube Studio accepts the token; False (and why, printed) when not."""
        message_type, data = await self._call(authentication_request(token, "koma-authenticate"),
                                              "koma-authenticate", self.reply_timeout)
        if message_type == "APIError":
            raise VtsError(f"VTube Studio refused AuthenticationRequest: {_error_text(data)}")
        if message_type != "AuthenticationResponse":
            raise VtsError(f"VTube Studio answered AuthenticationRequest with {message_type}")
        if data.get("authenticated") is True:
            return True
        reason = data.get("reason")
        _warn("VTube Studio refused the saved token" +
              (f": {reason}" if isinstance(reason, str) else ""))
        return False

    async def _authenticate(self):
        if self.token_file:
            token = read_token(self.token_file)
            if token and await self._authenticate_with(token):
                return
        _warn(f"VTube Studio: click \"Allow\" in its popup to let \"{PLUGIN_NAME}\" by "
              f"\"{PLUGIN_DEVELOPER}\" set parameters (waiting up to "
              f"{int(self.allow_timeout)} s)")
        message_type, data = await self._call(token_request("koma-token"), "koma-token",
                                              self.allow_timeout)
        if message_type == "APIError":
            raise VtsError("VTube Studio refused AuthenticationTokenRequest: "
                           f"{_error_text(data)}")
        token = data.get("authenticationToken")
        if message_type != "AuthenticationTokenResponse" or not isinstance(token, str) or \
                not token:
            raise VtsError(f"VTube Studio answered AuthenticationTokenRequest with "
                           f"{message_type} and no authenticationToken")
        if not self.token_file:
            _warn("warning: neither XDG_CONFIG_HOME nor HOME is set: the token is not saved "
                  "(--vts-token-file)")
        else:
            try:
                write_token(self.token_file, token)
            except OSError as error:
                _warn(f"warning: --vts-token-file: {error} (VTube Studio will ask again)")
        if not await self._authenticate_with(token):
            raise VtsError("VTube Studio refused the token it had just issued (was koma's "
                           "access revoked?)")

    def _fail(self, error):
        if self._failure is None:
            self._failure = error

    def _answer(self, text):
        """One answer to an inject: an APIError is printed once per errorID, or ends the
        stream (access revoked, the API turned off)."""
        try:
            message_type, _, data = parse_response(text)
        except ValueError as error:
            if self._errors_seen.get(-1, 0) == 0:
                _warn(f"warning: --vts: {error}")
            self._errors_seen[-1] = self._errors_seen.get(-1, 0) + 1
            return
        if message_type != "APIError":
            return
        error_id = _error_id(data)
        if error_id in _FATAL:  # the command prints it when the stream ends
            self._fail(VtsError(f"--vts: VTube Studio: {_error_text(data)}"))
            return
        if self._errors_seen.get(error_id, 0) == 0:  # each frame would repeat it
            _warn(f"warning: --vts: VTube Studio: {_error_text(data)}")
        self._errors_seen[error_id] = self._errors_seen.get(error_id, 0) + 1

    async def _read_answers(self):
        try:
            async for text in self._socket:
                self._answer(text)
        except self._websockets.exceptions.ConnectionClosed:
            pass
        self._fail(VtsError("--vts: VTube Studio closed the connection", closed=True))

    async def _send_values(self, request_id):
        try:
            await self._socket.send(inject_request(self._values, request_id))
        except self._websockets.exceptions.ConnectionClosed:
            self._fail(VtsError("--vts: VTube Studio closed the connection", closed=True))
            return False
        self.injects_sent += 1
        self._last_sent = time.monotonic()
        return True

    async def _frame(self, values, request_id):
        if self._failure is not None:
            self._failure_returned = True
            raise self._failure
        self._values = values
        # The request IDs tell a frame ("koma-frame-<grid frame>") from a re-send in VTube
        # Studio's log.
        if not await self._send_values(request_id):
            self._failure_returned = True
            raise self._failure

    async def _resend_loop(self):
        # Every 100 ms: re-sends the last values once they are resend_after old (0.5 s: VTube
        # Studio keeps an injected value about 1 s).
        while True:
            await asyncio.sleep(0.1)
            if self._failure is not None or self._values is None:
                continue
            if time.monotonic() - self._last_sent >= self.resend_after:
                self.resends += 1
                await self._send_values(f"koma-resend-{self.resends}")

    async def _close(self):
        resender = self._tasks[1] if len(self._tasks) > 1 else None
        if resender is not None:
            resender.cancel()
        if self._socket is None:
            return None
        if not getattr(self._socket, "closed", False):
            # The answers to the last frames: an APIError among them is still reported.
            await asyncio.sleep(0.1)
        for task in self._tasks:
            task.cancel()
        await self._socket.close()
        # A failure send() has raised has been reported already; the connection closing after
        # the last frame lost nothing.
        failure = self._failure
        if failure is not None and not self._failure_returned and not failure.closed:
            return failure
        return None
