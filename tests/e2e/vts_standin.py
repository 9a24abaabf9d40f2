"""A stand-in for VTube Studio's plugin API server, for tests/e2e/live_vts_e2e_test.sh. There is
no VTube Studio on Linux: this answers as the public API README documents
(github.com/DenchiSoft/VTubeStudio, "API Details": the envelope, AuthenticationTokenRequest,
AuthenticationRequest, InjectParameterDataRequest, APIError with ErrorID.cs's numbers) and
checks every request against the documented shapes. Debian's python3-websockets. Modes:

  serve PORT_FILE LOG [--token T] [--deny] [--valid-token T]... [--revoke-after N]
        [--close-after N]
      a WebSocket server on 127.0.0.1 (a free port, written to PORT_FILE) until SIGTERM. Each
      message received is a line of LOG (JSON: connection, monotonic time, the request, and
      the shape violations found). --token: the token AuthenticationTokenRequest is answered
      with; --deny: the user clicks Deny (APIError 50); --valid-token: a token issued before
      (the saved one) that AuthenticationRequest accepts; --revoke-after: the user revokes
      koma's access after N injects (the next are answered APIError 8); --close-after: VTube
      Studio closes the connection after N injects (it quits).
  check LOG FRAMES_JSONL --flow new|saved|refreshed [--mouth ID] [--left ID] [--right ID]
        [--mouth-min M] [--mouth-max M] [--max-gap S]
      no shape violation; the authentication flow (new: token request then authentication
      with the issued token; saved: authentication only; refreshed: the saved token refused,
      then a new one asked for and used); every frame of `koma live --json` injected once, in
      order, as "koma-frame-<grid frame>" with mouth (level - min) / (max - min) and both eyes
      eye_level, under the given parameter IDs; re-sends ("koma-resend-N") repeat the last
      frame's values; --max-gap: no two injects further apart than S seconds, and re-sends
      seen (the keep-alive VTube Studio needs at least once a second).
Exits 1 with the reasons on a failure.
"""
import argparse
import asyncio
import json
import os
import signal
import sys
import time

API_NAME = "VTubeStudioPublicAPI"
# VTube Studio's default input parameters (a subset of its list; plugins may add custom ones).
DEFAULT_PARAMETERS = {
    "FacePositionX", "FacePositionY", "FacePositionZ", "FaceAngleX", "FaceAngleY", "FaceAngleZ",
    "MouthSmile", "MouthOpen", "Brows", "TongueOut", "EyeOpenLeft", "EyeOpenRight", "EyeLeftX",
    "EyeLeftY", "EyeRightX", "EyeRightY", "CheekPuff", "FaceAngry", "BrowLeftY", "BrowRightY",
    "MouthX", "VoiceVolume", "VoiceFrequency", "VoiceVolumePlusMouthOpen",
}
KNOWN_TYPES = {"APIStateRequest", "AuthenticationTokenRequest", "AuthenticationRequest",
               "InjectParameterDataRequest"}


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def check_envelope(request):
    """(violations, errorID or None) of the fields every request has."""
    if not isinstance(request, dict):
        return ["not a JSON object"], 2
    bad = []
    extra = set(request) - {"apiName", "apiVersion", "requestID", "messageType", "data",
                            "timestamp"}
    if extra:
        bad.append(f"unknown fields {sorted(extra)}")
    if request.get("apiName") != API_NAME:
        return bad + [f"apiName {request.get('apiName')!r}"], 3
    if request.get("apiVersion") != "1.0":
        return bad + [f"apiVersion {request.get('apiVersion')!r}"], 4
    rid = request.get("requestID")
    if rid is not None and not (isinstance(rid, str) and 1 <= len(rid) <= 64 and rid.isascii()):
        return bad + [f"requestID {rid!r}"], 5
    if rid is None:
        bad.append("no requestID (koma always sends one)")
    mtype = request.get("messageType")
    if not isinstance(mtype, str) or not mtype:
        return bad + ["messageType missing"], 6
    if mtype not in KNOWN_TYPES:
        return bad + [f"messageType {mtype!r}"], 7
    if not isinstance(request.get("data"), dict):
        bad.append("data is not an object (koma always sends one)")
    return bad, None


def check_plugin_names(data, bad):
    for field in ("pluginName", "pluginDeveloper"):
        value = data.get(field)
        if not (isinstance(value, str) and 3 <= len(value) <= 32):
            bad.append(f"{field} {value!r} must be a string of 3..32 characters")


class StandIn:
    def __init__(self, args):
        self.args = args
        self.log = open(args.log, "a", buffering=1)
        self.issued = set(args.valid_token)
        self.connections = 0

    def response(self, request, mtype, data):
        return json.dumps({
            "apiName": API_NAME, "apiVersion": "1.0", "timestamp": int(time.time() * 1000),
            "messageType": mtype, "requestID": request.get("requestID") or "stand-in",
            "data": data,
        })

    def error(self, request, error_id, message):
        return self.response(request if isinstance(request, dict) else {}, "APIError",
                             {"errorID": error_id, "message": message})

    def answer(self, request, state, bad):
        mtype = request["messageType"]
        data = request.get("data") if isinstance(request.get("data"), dict) else {}
        if mtype == "APIStateRequest":
            return self.response(request, "APIStateResponse", {
                "active": True, "vTubeStudioVersion": "stand-in",
                "currentSessionAuthenticated": state["authenticated"]})
        if mtype == "AuthenticationTokenRequest":
            check_plugin_names(data, bad)
            extra = set(data) - {"pluginName", "pluginDeveloper", "pluginIcon"}
            if extra:
                bad.append(f"AuthenticationTokenRequest: unknown data fields {sorted(extra)}")
            if "pluginIcon" in data:
                bad.append("pluginIcon sent (koma sends none)")
            if bad:
                return self.error(request, 52, "plugin name or developer invalid")
            if self.args.deny:
                return self.error(request, 50, "User has denied API access for your plugin.")
            self.issued.add(self.args.token)
            return self.response(request, "AuthenticationTokenResponse",
                                 {"authenticationToken": self.args.token})
        if mtype == "AuthenticationRequest":
            check_plugin_names(data, bad)
            token = data.get("authenticationToken")
            if not isinstance(token, str) or not token:
                bad.append("authenticationToken missing")
                return self.error(request, 100, "authenticationToken missing")
            if bad:
                return self.error(request, 101, "plugin name or developer missing")
            ok = token in self.issued
            state["authenticated"] = ok
            return self.response(request, "AuthenticationResponse", {
                "authenticated": ok,
                "reason": "Token valid. The plugin is authenticated for the duration of this "
                          "session." if ok else "Token invalid or revoked."})
        # InjectParameterDataRequest
        state["injects"] += 1
        if self.args.revoke_after is not None and state["injects"] > self.args.revoke_after:
            state["authenticated"] = False
        if not state["authenticated"]:
            if self.args.revoke_after is None:
                bad.append("InjectParameterDataRequest before authentication")
            return self.error(request, 8, "This request requires authentication.")
        extra = set(data) - {"faceFound", "mode", "parameterValues"}
        if extra:
            bad.append(f"InjectParameterDataRequest: unknown data fields {sorted(extra)}")
        if "faceFound" in data and not isinstance(data["faceFound"], bool):
            bad.append(f"faceFound {data['faceFound']!r} is not a boolean")
        if data.get("mode", "set") not in ("set", "add"):
            bad.append(f"mode {data.get('mode')!r}")
            return self.error(request, 455, "mode unknown")
        values = data.get("parameterValues")
        if not isinstance(values, list) or not values:
            bad.append("parameterValues missing or empty")
            return self.error(request, 450, "no data provided")
        for value in values:
            if not isinstance(value, dict) or not isinstance(value.get("id"), str):
                bad.append(f"parameter value {value!r} has no string id")
                return self.error(request, 450, "no data provided")
            if set(value) - {"id", "value", "weight"}:
                bad.append(f"parameter value {value!r}: unknown fields")
            if not is_number(value.get("value")) or abs(value["value"]) > 1000000:
                bad.append(f"parameter value {value!r}: value not a number in +-1000000")
                return self.error(request, 451, "value invalid")
            if "weight" in value and not (is_number(value["weight"]) and
                                          0 <= value["weight"] <= 1):
                bad.append(f"parameter value {value!r}: weight not in 0..1")
                return self.error(request, 452, "weight invalid")
        for value in values:
            if value["id"] not in DEFAULT_PARAMETERS:  # not a violation: VTube Studio's answer
                return self.error(request, 453,
                                  f"Parameter {value['id']} not found.")
        return self.response(request, "InjectParameterDataResponse", {})

    async def handle(self, websocket, path=None):
        self.connections += 1
        connection = self.connections
        state = {"authenticated": False, "injects": 0}
        try:
            async for text in websocket:
                received = time.monotonic()
                bad = []
                try:
                    request = json.loads(text)
                except ValueError:
                    request = None
                    bad.append("not JSON")
                if request is not None:
                    bad, error_id = check_envelope(request)
                    if error_id is not None:
                        reply = self.error(request, error_id, "; ".join(bad))
                    else:
                        reply = self.answer(request, state, bad)
                else:
                    reply = self.error({}, 2, "JSON invalid")
                if isinstance(text, bytes):
                    bad.append("a binary message (the README recommends text)")
                self.log.write(json.dumps({"connection": connection, "t": received,
                                           "request": request, "violations": bad}) + "\n")
                await websocket.send(reply)
                if (self.args.close_after is not None and
                        state["injects"] >= self.args.close_after):
                    await websocket.close()
                    break
        except Exception as e:  # a connection that ends abruptly is logged, not fatal
            self.log.write(json.dumps({"connection": connection, "t": time.monotonic(),
                                       "closed": repr(e)}) + "\n")

    async def serve(self):
        import websockets  # python3-websockets

        stop = asyncio.get_running_loop().create_future()
        asyncio.get_running_loop().add_signal_handler(signal.SIGTERM, stop.set_result, None)
        async with websockets.serve(self.handle, "127.0.0.1", 0, ping_interval=None) as server:
            port = server.sockets[0].getsockname()[1]
            with open(self.args.port_file + ".tmp", "w") as out:
                out.write(str(port))
            os.rename(self.args.port_file + ".tmp", self.args.port_file)
            await stop


def check(args):
    entries = [json.loads(line) for line in open(args.log) if line.strip()]
    frames = [json.loads(line) for line in open(args.frames) if line.strip()]
    errors = []
    requests = [e for e in entries if "request" in e]
    for e in requests:
        for violation in e["violations"]:
            errors.append(f"{e['request'].get('requestID') if e['request'] else '?'}: "
                          f"{violation}")
    types = [e["request"]["messageType"] for e in requests]
    auth = [t for t in types if t != "InjectParameterDataRequest"]
    want_auth = {
        "new": ["AuthenticationTokenRequest", "AuthenticationRequest"],
        "saved": ["AuthenticationRequest"],
        "refreshed": ["AuthenticationRequest", "AuthenticationTokenRequest",
                      "AuthenticationRequest"],
    }[args.flow]
    if auth != want_auth:
        errors.append(f"authentication flow {auth}, want {want_auth}")
    if types[:len(want_auth)] != want_auth:
        errors.append(f"requests start {types[:len(want_auth) + 1]}, want the flow first")
    if len({e["connection"] for e in requests}) != 1:
        errors.append("more than one connection")
    injects = [e for e in requests if e["request"]["messageType"] == "InjectParameterDataRequest"]
    frame_injects = [e for e in injects if e["request"]["requestID"].startswith("koma-frame-")]
    resends = [e for e in injects if e["request"]["requestID"].startswith("koma-resend-")]
    if len(frame_injects) + len(resends) != len(injects):
        errors.append("injects that are neither koma-frame-N nor koma-resend-N")
    ids = [f"koma-frame-{f['grid_frame']}" for f in frames]
    got_ids = [e["request"]["requestID"] for e in frame_injects]
    if got_ids != ids:
        errors.append(f"{len(got_ids)} frame injects for {len(frames)} frames, or out of order")
    lo, hi = args.mouth_min, args.mouth_max

    def want_values(frame):
        mouth = min(1.0, max(0.0, (frame["mouth_level"] - lo) / (hi - lo)))
        return [(args.mouth, mouth), (args.left, frame["eye_level"]),
                (args.right, frame["eye_level"])]

    def values(entry):
        return [(v["id"], v["value"]) for v in entry["request"]["data"]["parameterValues"]]

    def same(a, b):
        return len(a) == len(b) and all(x[0] == y[0] and abs(x[1] - y[1]) < 1e-12
                                        for x, y in zip(a, b))

    for entry, frame in zip(frame_injects, frames):
        if not same(values(entry), want_values(frame)):
            errors.append(f"{entry['request']['requestID']}: {values(entry)}, "
                          f"want {want_values(frame)}")
            break
    last = None
    for entry in injects:
        if entry["request"]["requestID"].startswith("koma-frame-"):
            last = values(entry)
        elif last is None or not same(values(entry), last):
            errors.append(f"{entry['request']['requestID']} {values(entry)} does not repeat "
                          f"the last frame's {last}")
    for entry in injects:
        data = entry["request"]["data"]
        if data.get("faceFound") is not False or data.get("mode") != "set":
            errors.append(f"{entry['request']['requestID']}: faceFound {data.get('faceFound')}, "
                          f"mode {data.get('mode')}, want false and set")
            break
    gaps = [b["t"] - a["t"] for a, b in zip(injects, injects[1:])]
    max_gap = max(gaps) if gaps else 0.0
    if args.max_gap is not None:
        if max_gap > args.max_gap:
            errors.append(f"injects {max_gap:.3f} s apart, more than {args.max_gap} s")
        if not resends:
            errors.append("no re-sends while frames were more than 0.5 s apart")
    print(f"{len(requests)} requests: flow {auth}, {len(frame_injects)} frames injected, "
          f"{len(resends)} re-sends, largest gap {max_gap:.3f} s")
    if errors:
        print("FAIL:\n  " + "\n  ".join(errors[:20]), file=sys.stderr)
        sys.exit(1)


def main():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="mode", required=True)
    serve = sub.add_parser("serve")
    serve.add_argument("port_file")
    serve.add_argument("log")
    serve.add_argument("--token", default="stand-in-token-0001")
    serve.add_argument("--deny", action="store_true")
    serve.add_argument("--valid-token", action="append", default=[])
    serve.add_argument("--revoke-after", type=int)
    serve.add_argument("--close-after", type=int)
    chk = sub.add_parser("check")
    chk.add_argument("log")
    chk.add_argument("frames")
    chk.add_argument("--flow", choices=["new", "saved", "refreshed"], required=True)
    chk.add_argument("--mouth", default="MouthOpen")
    chk.add_argument("--left", default="EyeOpenLeft")
    chk.add_argument("--right", default="EyeOpenRight")
    chk.add_argument("--mouth-min", type=float, default=0.0)
    chk.add_argument("--mouth-max", type=float, default=1.0)
    chk.add_argument("--max-gap", type=float)
    args = parser.parse_args()
    if args.mode == "serve":
        asyncio.run(StandIn(args).serve())
    else:
        check(args)


if __name__ == "__main__":
    main()
