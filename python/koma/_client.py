"""koma.Client: the koma RPCs and the health check, from a file path or its text; live()
streams a voice (koma/_live.py)."""
import json
import os
import re

import grpc

from koma import _format_table, _health_pb2, _live, _live_sources, _options, _presets
from koma import _sheet_timing, _xdts
from koma._errors import KomaError
from koma._results import CurvesResult, LipBlinkResult, SkeletalResult
from koma.v1 import motion_pb2, retime_pb2, retime_pb2_grpc

# As the C++ client: a 100k-frame, 31-joint clip is about 77 MB on the wire.
MAX_MESSAGE_BYTES = 256 * 1024 * 1024
DEFAULT_TIMEOUT_S = 60.0


class Positions:
    """A skeletal clip as world joint positions (RetimeSkeletal's positions form), for tools
    that evaluate their own rig (Blender, Maya): no BVH needed.

    Args:
        names: joint names, one per joint.
        parents: per joint, the index of its parent joint, -1 for a root; parents come
            before their children.
        frame_time: seconds per frame (1 / fps), > 0.
        positions: frame-major world positions in the clip's length unit: either a flat
            sequence of frames x joints x 3 numbers, or a sequence of frames, each a sequence
            of joints, each (x, y, z).
    """

    def __init__(self, names, parents, frame_time, positions):
        if len(names) != len(parents):
            raise ValueError(f"Positions: {len(names)} names but {len(parents)} parents")
        self.names = list(names)
        self.parents = [int(p) for p in parents]
        self.frame_time = float(frame_time)
        flat = []
        for item in positions:
            if hasattr(item, "__iter__"):
                for joint in item:
                    if hasattr(joint, "__iter__"):
                        flat.extend(float(v) for v in joint)
                    else:
                        flat.append(float(joint))
            else:
                flat.append(float(item))
        per_frame = 3 * len(self.names)
        if per_frame == 0 or len(flat) % per_frame != 0:
            raise ValueError(f"Positions: {len(flat)} numbers is not frames x {len(self.names)} "
                             "joints x 3")
        self.values = flat
        self.frame_count = len(flat) // per_frame

    def to_proto(self):
        motion = motion_pb2.SkeletalMotion()
        for name, parent in zip(self.names, self.parents):
            motion.skeleton.joints.add(name=name, parent=parent)
        motion.frame_time = self.frame_time
        motion.frame_count = self.frame_count
        motion.positions.values.extend(self.values)
        return motion


def _looks_like_text(source, starts):
    stripped = source.lstrip()
    return "\n" in source or any(stripped.startswith(s) for s in starts)


def _read_source(source, text_starts):
    """(the file's bytes, its path or None) of a path, a path-like, bytes or a text."""
    if isinstance(source, bytes):
        return source, None
    if isinstance(source, os.PathLike) or (isinstance(source, str) and
                                           not _looks_like_text(source, text_starts)):
        path = os.fspath(source)
        with open(path, "rb") as f:
            return f.read(), path
    if isinstance(source, str):
        return source.encode("utf-8"), None
    raise TypeError(f"expected a path, a file's text (str) or bytes, got {type(source).__name__}")


def _bvh_length(data):
    """(frames, frames per second) of a BVH's MOTION section, (0, 0.0) when it has none that
    reads (the server then checks a given timing against the clip and names the field)."""
    text = data.decode("utf-8", "replace") if isinstance(data, bytes) else data
    motion = text.find("MOTION")
    frames = re.search(r"Frames:\s*(\d+)", text[motion:]) if motion >= 0 else None
    frame_time = re.search(r"Frame Time:\s*([0-9.eE+-]+)", text[motion:]) if motion >= 0 else None
    try:
        seconds = float(frame_time.group(1)) if frame_time else 0.0
        return (int(frames.group(1)), 1.0 / seconds) if frames and seconds > 0 else (0, 0.0)
    except ValueError:
        return 0, 0.0


def _sent_whole_format(data, path):
    """The key of a skeletal format the server reads whole (glTF, FBX), told as `koma skeletal`
    tells it (formats/format_table.h): by the name, else the first bytes; None for BVH."""
    named, sniffed = _format_table.format_from_name(path), _format_table.sniff(data)
    for row in _format_table.FORMATS:
        if row["sent_whole"] and row["key"] in (named, sniffed):
            return row["key"]
    return None


def _is_csv(data, path, file_format):
    if file_format is not None:
        if file_format not in ("motion3", "csv", "spine"):
            raise ValueError(f"format: {file_format!r} is not 'motion3', 'csv' or 'spine'")
        return file_format == "csv"
    if path is not None:
        return _format_table.format_from_name(path) == "csv"
    # Not JSON (a UTF-8 byte order mark, which Windows tools write, says nothing).
    return not _format_table.is_json(data)


def _is_spine(data, file_format):
    """A Spine skeleton JSON: its first key is "skeleton" (as Spine exports it), or it has a
    "skeleton" key and no "Meta" (the format table's rule, as koma's reader guesses)."""
    if file_format is not None:
        return file_format == "spine"
    return _format_table.matches("spine", data)


def _credentials(tls):
    """grpc.ChannelCredentials for `tls`, or None for plaintext."""
    if tls is None or tls is False:
        return None
    if tls is True:
        return grpc.ssl_channel_credentials()
    if isinstance(tls, grpc.ChannelCredentials):
        return tls
    if isinstance(tls, (str, os.PathLike)):
        tls = (tls, None, None)
    if isinstance(tls, tuple) and len(tls) == 3:
        def read(path):
            if path is None:
                return None
            with open(path, "rb") as f:
                return f.read()
        ca, cert, key = (read(p) for p in tls)
        if (cert is None) != (key is None):
            raise ValueError("tls: a client certificate needs its key, and a key its certificate")
        return grpc.ssl_channel_credentials(root_certificates=ca, private_key=key,
                                            certificate_chain=cert)
    raise TypeError("tls: expected False, True, a CA file path, (ca, cert, key) paths or "
                    "grpc.ChannelCredentials")


class Client:
    """A connection to a koma_server.

    Args:
        address: "host:port" of the server, e.g. "127.0.0.1:50051".
        timeout: seconds each call may take (its gRPC deadline), > 0; default 60. A call
            that takes longer raises KomaError with code DEADLINE_EXCEEDED.
        tls: False (plaintext, the default), True (TLS with the system's CAs), the path of a
            PEM CA file, a (ca, client_cert, client_key) tuple of PEM paths (mutual TLS;
            ca may be None), or a grpc.ChannelCredentials.

    Every call raises KomaError (gRPC code and the server's message naming the field) when
    the server refuses it, TypeError / ValueError for a misnamed or mistyped option before
    sending anything, and OSError when an input path cannot be read. Usable as a context
    manager; close() closes the channel.
    """

    def __init__(self, address, timeout=DEFAULT_TIMEOUT_S, tls=False):
        if not isinstance(address, str) or not address:
            raise TypeError(f"address: expected 'host:port', got {address!r}")
        if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or \
                not timeout > 0:
            raise ValueError(f"timeout: {timeout!r} must be a number of seconds > 0")
        self.address = address
        self.timeout = float(timeout)
        options = [("grpc.max_receive_message_length", MAX_MESSAGE_BYTES),
                   ("grpc.max_send_message_length", MAX_MESSAGE_BYTES)]
        credentials = _credentials(tls)
        if credentials is None:
            self._channel = grpc.insecure_channel(address, options=options)
        else:
            self._channel = grpc.secure_channel(address, credentials, options=options)
        self._stub = retime_pb2_grpc.RetimeStub(self._channel)
        self._health = self._channel.unary_unary(
            "/grpc.health.v1.Health/Check",
            request_serializer=_health_pb2.HealthCheckRequest.SerializeToString,
            response_deserializer=_health_pb2.HealthCheckResponse.FromString)

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _call(self, method, request):
        try:
            return method(request, timeout=self.timeout)
        except grpc.RpcError as error:
            raise KomaError.from_rpc_error(error) from None

    def retime_skeletal(self, source, preset=None, **options):
        """Inbetween omission and holds on a skeletal clip (RetimeSkeletal).

        With no options the server's anime defaults apply: on threes (8 drawings a second)
        with one omission a second of the take; preset="paper" (or any of omissions, holds,
        max_hold) asks for the paper's counts instead (docs/semantics.md).

        Args:
            source: a BVH, glTF or FBX file's path (str or path-like; .glb, .gltf, .vrm and
                .vrma are glTF, .fbx binary FBX 7.1-7.7), a BVH's text (str containing a
                newline or starting with "HIERARCHY"), a file's bytes (glTF and FBX by their
                content), or a koma.Positions clip.
            preset: "twos", "threes", "snappy", "subtle" or "paper", as `koma skeletal
                --preset` (docs/usage.md); options given beside it win.
            **options: RetimeSkeletalRequest fields: omissions (steps, int), holds (steps,
                int), max_hold (frames, int), keep_length (bool), order ("OMIT_THEN_HOLD" or
                "HOLD_THEN_OMIT"), joint_weights (list of float), root_relative (bool),
                camera (16 floats, column-major view-projection), return_motion (bool),
                timing_fps (frames per second of the film grid; unset 24, 0 none),
                output_rate ("SOURCE_RATE" or "TIMING_RATE"), omissions_per_second (an
                omission rate instead of omissions), drawings_per_second (12 on twos, 8 on
                threes), cut_neighbour_ratio and cut_median_ratio (cuts; 0: none), and for glTF
                gltf_animations (names or indices as str), gltf_retime_none, gltf_source_fps,
                gltf_keys ("GLTF_KEYS_STEP" or "GLTF_KEYS_LINEAR"), gltf_keep_original; for
                FBX fbx_take (the take's name; default the file's current take). Frame
                counts are in grid frames when a grid is used. timing_from: the path of an
                edited XDTS sheet or --timing CSV whose timing is applied instead of computing
                one, as `koma skeletal --timing-from` (cell N shows source frame N, a blank
                cell holds the frame before; raises koma.SheetError naming the track, frame
                and cell when it does not fit the clip).

        Returns:
            SkeletalResult: with a BVH source, .output is the retimed BVH text, byte for
            byte what `koma skeletal IN -o OUT` writes; with a glTF source, .output_bytes
            (and .write(path)) the retimed file, .animations one dict per retimed animation;
            with Positions, .response.motion holds the retimed positions.
        """
        request = retime_pb2.RetimeSkeletalRequest()
        timing_from = options.pop("timing_from", None)
        options = _presets.apply(_presets.SKELETAL, preset, options)
        _options.fill(request, options, skip=("motion", "bvh_text", "gltf", "fbx"))
        path = None
        frame_count, source_fps = 0, 0.0
        if isinstance(source, Positions):
            request.motion.CopyFrom(source.to_proto())
            frame_count = source.frame_count
            source_fps = 1.0 / source.frame_time if source.frame_time > 0 else 0.0
        else:
            bvh_starts = tuple(s.decode() for s in _format_table.row("bvh")["text_starts"])
            data, path = _read_source(source, bvh_starts)
            key = _sent_whole_format(data, path) or "bvh"
            setattr(request, _format_table.request_field(key, "RetimeSkeletalRequest"), data)
            if key == "bvh":
                frame_count, source_fps = _bvh_length(data)
        warnings = []
        if timing_from is not None:
            frames, warnings = _sheet_timing.skeletal_source_frames(
                timing_from, _xdts.clip_name(path or "-", ""), frame_count, source_fps,
                options.get("timing_fps"))
            request.given_timing.source_frames.extend(frames)
        result = SkeletalResult(self._call(self._stub.RetimeSkeletal, request))
        result.source_path = path
        result.warnings = list(warnings) + list(result.warnings)
        return result

    def _curve_request(self, request, source, file_format, csv_fps, animation=None):
        """Fills the request's file; returns (its path or None, a function giving its fps)."""
        data, path = _read_source(source, ("{", "frame,"))
        if _is_spine(data, file_format):
            if csv_fps is not None:
                raise ValueError("csv_fps: only for a CSV input")
            request.spine_json = data
            if animation is not None:
                if "spine_animation" in request.DESCRIPTOR.fields_by_name:
                    request.spine_animation = animation
                else:  # LipBlink: the animation the slots are keyed in
                    request.spine.animation = animation
            return path, lambda: float(json.loads(data)["skeleton"].get("fps", 30))
        if animation is not None:
            raise ValueError("animation: only for a Spine skeleton")
        if _is_csv(data, path, file_format):
            request.csv_text = data
            if csv_fps is not None:
                _options.fill(request, {"csv_fps": csv_fps})
            return path, lambda: request.csv_fps or 30.0
        if csv_fps is not None:
            raise ValueError("csv_fps: only for a CSV input")
        request.motion3_json = data
        return path, lambda: float(json.loads(data)["Meta"]["Fps"])

    def retime_curves(self, source, format=None, csv_fps=None, animation=None, preset=None,
                      **options):
        """Koma-uchi on twos/threes with tame/tsume spacing (RetimeCurves).

        Args:
            source: a motion3.json, Spine skeleton JSON or per-frame CSV file's path, its text
                or its bytes.
            format: "motion3", "spine" or "csv"; default from the path's extension (.csv) or
                the text (JSON starts with "{"; a Spine skeleton's first key is "skeleton").
            csv_fps: frames per second of a CSV input (default 30).
            animation: a Spine skeleton's animation to retime (its bone timelines are the
                curves, "torso/rotate", "torso/translate.x", ...); may be left out when the
                skeleton has one animation with bone keys.
            preset: "twos", "threes", "snappy", "subtle" or "paper", as `koma curves
                --preset` (docs/usage.md); options given beside it win.
            **options: RetimeCurvesRequest fields: key_frames (frames, list of int),
                frames_per_drawing (1 on ones, 2 on twos, 3 on threes), tame and tsume
                (strengths >= 1), curve_overrides (list of {"curve_id", "frames_per_drawing"}),
                segment_overrides (list of {"segment", "frames_per_drawing", "tame",
                "tsume"}), timing_fps (film grid, frames per second; unset 24, 0 none),
                merge_key_poses (False: every keyframe time a key pose), timing_groups
                (list of {"name", "ids" (ids or patterns such as "ParamHair*"),
                "frames_per_drawing", "tame", "tsume", "key_frames", "mode" ("GROUP_STEP",
                "GROUP_KEEP": the curves as they came in, "GROUP_LIP_BLINK": LipBlink draws
                the mouth and eyes, the rest stepped), and for GROUP_LIP_BLINK "mouth", "eyes",
                "seed" as lip_blink's}; unset: Live2D's default grouping, face (GROUP_LIP_BLINK)
                / hair / body), default_timing_groups (False: one group).

        Returns:
            CurvesResult whose .output is the retimed file in the input's format, byte for
            byte what `koma curves IN -o OUT` writes (for a Spine skeleton, with
            `--animation` naming the one animation).
        """
        request = retime_pb2.RetimeCurvesRequest()
        timing_from = options.pop("timing_from", None)
        options = _presets.apply(_presets.CURVES, preset, options)
        _options.fill(request, options,
                      skip=("curves", "motion3_json", "csv_text", "csv_fps", "spine_json",
                            "spine_animation"))
        path, _ = self._curve_request(request, source, format, csv_fps, animation)
        warnings = []
        if timing_from is not None:
            if request.HasField("spine_json"):
                raise ValueError("timing_from: not for a Spine skeleton")
            # The sheet's cells name the drawings of koma's own answer (koma curves).
            computed = self._call(self._stub.RetimeCurves, request)
            warnings = _sheet_timing.curves_given_timings(
                timing_from, _xdts.clip_name(path or "-", os.fspath(timing_from)), computed,
                request)
        result = CurvesResult(self._call(self._stub.RetimeCurves, request))
        result.source_path = path
        result.warnings = list(warnings) + list(getattr(result, "warnings", []))
        return result

    def lip_blink(self, source=None, format=None, csv_fps=None, audio=None, rhubarb_cues=None,
                  animation=None, mouth_slot=None, mouth_attachments=None, eye_slots=None,
                  eye_attachments=None, preset=None, **options):
        """Three-drawing mouth flaps and anime blinks (LipBlink).

        Args:
            source, format, csv_fps: as retime_curves: the motion whose mouth and eyes are
                converted. Optional with audio or rhubarb_cues: without it koma writes a new
                motion (voice_motion_fps, default 30) covering the recording.
            audio: a recording (WAV, FLAC, Ogg Vorbis/Opus, MP3): its path (str or path-like)
                or its bytes. The speech and the mouth drawings come from it
                (docs/semantics.md, "LipBlink from a voice"); the mouth curve (mouth ids,
                default ParamMouthOpenY) is added when the motion lacks it.
            rhubarb_cues: Rhubarb Lip Sync's mouth cues (its JSON or TSV) in place of audio: a
                path, the text or its bytes.
            animation, mouth_slot, mouth_attachments, eye_slots, eye_attachments: with a Spine
                skeleton as source (LipBlinkRequest.spine): the animation the slots are keyed
                in (required; added when missing), the mouth slot and its closed, mid, open
                attachments (default SLOT_closed, SLOT_mid, SLOT_open), the eye slots (list)
                and their open, half, closed attachments (default SLOT_open, SLOT_half,
                SLOT_closed). mouth.speech then counts the skeleton's frames (skeleton.fps).
            preset: "twos", "threes", "snappy", "subtle" or "paper", as `koma lipblink
                --preset` (docs/usage.md); options given beside it win.
            **options: LipBlinkRequest fields: mouth (dict: ids, mode "MOUTH_RANDOM" or
                "MOUTH_FOLLOW", frames_per_shape (frames), mid_ratio, min, max, speech as
                [(begin, end)] frames), eyes (dict: ids, mid_ratio, threshold, min, max,
                linked, auto_blink {"enabled", "mean_interval_s" (s), "spread_s" (s), "hold"
                (frames), "keep"}), seed (int), timing_fps (film grid, frames per second);
                with a voice also voice_settings (dict of LipBlinkVoiceSettings: dB
                thresholds, bridge_gap_frames, min_speech_frames, ...), voice_motion_fps,
                voice_output ("VOICE_OUTPUT_MOTION3_JSON" or "VOICE_OUTPUT_CSV").

        Returns:
            LipBlinkResult whose .output is the converted file in the input's format (a new
            motion3.json or CSV for a voice alone; for a Spine skeleton the skeleton with the
            slots' attachment timelines written), byte for byte what `koma lipblink` writes;
            with a voice also .voice (the analysis) and .rhubarb_json / .rhubarb_tsv.
        """
        request = retime_pb2.LipBlinkRequest()
        timing_from = options.pop("timing_from", None)
        options = _presets.apply(_presets.LIP_BLINK, preset, options)
        _options.fill(request, options, skip=("curves", "motion3_json", "csv_text", "csv_fps",
                                              "audio", "rhubarb_cues", "spine_json", "spine"))
        if audio is not None and rhubarb_cues is not None:
            raise ValueError("audio, rhubarb_cues: give one voice, not both")
        # The sheet's name (xdts()): the motion's file, else the voice's, as `koma lipblink`.
        voice_path = None
        if audio is not None:
            if isinstance(audio, (bytes, bytearray)):
                request.audio = bytes(audio)
            elif isinstance(audio, (str, os.PathLike)):
                voice_path = os.fspath(audio)
                with open(voice_path, "rb") as f:
                    request.audio = f.read()
            else:
                raise TypeError(f"audio: expected a path or bytes, got {type(audio).__name__}")
        if rhubarb_cues is not None:
            request.rhubarb_cues, voice_path = _read_source(rhubarb_cues, ("{", "0"))
        slots = {"mouth_slot": mouth_slot, "mouth_attachments": mouth_attachments,
                 "eye_slots": eye_slots, "eye_attachments": eye_attachments}
        if source is not None:
            path, fps = self._curve_request(request, source, format, csv_fps, animation)
            if request.HasField("spine_json"):
                for name, value in slots.items():
                    if value is None:
                        continue
                    if name == "mouth_slot":
                        request.spine.mouth_slot = value
                    else:
                        getattr(request.spine, name).extend(
                            [value] if isinstance(value, str) else list(value))
            elif any(v is not None for v in slots.values()):
                raise ValueError("mouth_slot, mouth_attachments, eye_slots, eye_attachments: "
                                 "only for a Spine skeleton")
        elif animation is not None or any(v is not None for v in slots.values()):
            raise ValueError("animation, mouth_slot, eye_slots: only with a Spine skeleton "
                             "as source")
        elif audio is None and rhubarb_cues is None:
            raise TypeError("lip_blink: a source motion, audio or rhubarb_cues is required")
        else:
            # A new motion at voice_motion_fps (unset or 0: 30, as the server writes it).
            path, fps = voice_path, lambda: request.voice_motion_fps or 30.0
        warnings = []
        if timing_from is not None:
            if source is None or audio is not None or rhubarb_cues is not None or \
                    request.HasField("spine_json"):
                raise ValueError("timing_from: not with a voice (audio, rhubarb_cues) or a "
                                 "Spine skeleton")
            # The sheet's cells name koma's own answer's tracks (koma lipblink).
            computed = self._call(self._stub.LipBlink, request)
            warnings = _sheet_timing.lip_blink_given_timing(
                timing_from, _xdts.clip_name(path or "-", os.fspath(timing_from)), fps(),
                computed, request)
        result = LipBlinkResult(self._call(self._stub.LipBlink, request))
        result.source_path = path
        result._source_fps = fps
        result.warnings = list(warnings) + list(getattr(result, "warnings", []))
        return result

    def live(self, audio_chunks, sample_rate, channels, sample_format="s16le", *, lookahead=2,
             seed=None, timing_fps=None, mouth=None, eyes=None, voice_settings=None,
             timeout=None):
        """Mouth flaps and blinks from a live voice (LiveLipBlink): a bidirectional stream.

        Args:
            audio_chunks: an iterable of bytes: interleaved little-endian samples in
                sample_format, each chunk whole sample frames (channels x 2 or 4 bytes), sent
                as it comes (e.g. 10 ms at a time: AudioFile(...).chunks() or
                Microphone().chunks()). The stream ends (the client half-closes) when it ends.
            sample_rate: samples per second (1000-384000); channels: interleaved channels
                (mixed to mono by the server; at most its --max_audio_channels).
            sample_format: "s16le" (16-bit integers) or "f32le" (32-bit floats).
            lookahead: grid frames of audio past a frame's end the server waits for before
                deciding it, 0-3 (each costs 41.7 ms of delay and agrees better with
                lip_blink(audio=...)).
            seed: the random mouth shapes' and auto-blinks' seed (unset: the server's).
            timing_fps: the film grid (unset: 24).
            mouth, eyes, voice_settings: as lip_blink's (dicts of MouthSettings,
                EyeSettings, LipBlinkVoiceSettings fields), e.g. mouth={"mode":
                "MOUTH_FOLLOW"}, eyes={"auto_blink": {"enabled": True}}; no ids, no speech,
                no eye threshold or linked (there are no curves).
            timeout: the whole stream's deadline in seconds; default none (a live stream
                lasts as long as its audio), not the client's per-call timeout.

        Returns:
            an iterator of LiveFrame, one per film-grid frame from grid_frame 0, each as soon
            as the server decides it. Stopping early (break, close()) cancels the stream.

        Raises (while iterating): KomaError with the server's code and message, which names the
        setup's field ("setup.sample_rate: 0 must be in [1000, 384000] ...") or the audio
        message; what audio_chunks raised, re-raised. TypeError / ValueError for a wrong option
        before anything is sent.
        """
        _live.check_chunks(audio_chunks)
        options = {"timing_fps": timing_fps, "mouth": mouth, "eyes": eyes,
                   "voice_settings": voice_settings}
        setup = _live.setup_request(sample_rate, channels, sample_format, lookahead, seed,
                                    options)
        if timeout is not None and not timeout > 0:
            raise ValueError(f"timeout: {timeout!r} must be a number of seconds > 0, or None")
        return _live.stream(self._stub, setup, audio_chunks, timeout)

    def live_file(self, path, speed=1.0, seconds=None, chunk_ms=10, **options):
        """live() on a recording played at real time (speed 1; 2 twice as fast; 0 as fast as
        the server takes it): 10 ms chunks paced by time.monotonic. WAV through Python's wave
        module, other formats (FLAC, Ogg, MP3) through sox when it is on PATH
        (koma.AudioFile). seconds: play only that much. **options: as live()'s."""
        source = _live_sources.AudioFile(path)
        chunks = source.chunks(chunk_ms=chunk_ms, speed=speed, seconds=seconds)
        return self.live(chunks, source.sample_rate, source.channels, source.sample_format,
                         **options)

    def health(self, service=""):
        """The server's grpc.health.v1 status: "SERVING" when it takes calls ("NOT_SERVING"
        while it shuts down). `service` "" is the whole server, "koma.v1.Retime" the service."""
        response = self._call(self._health, _health_pb2.HealthCheckRequest(service=service))
        return _health_pb2.HealthCheckResponse.ServingStatus.Name(response.status)
