"""Live frames to a VMC-protocol receiver (VSeeFace, VNyan, Warudo, ...): per frame one OSC
bundle over UDP of
    /VMC/Ext/Blend/Val "A" <how open the mouth is, 0..1>
    /VMC/Ext/Blend/Val "Blink" <1 - how open the eyes are, 0..1>
    /VMC/Ext/Blend/Apply
through liblo (Debian package python3-liblo), imported only here. As the C++ `koma live
--vmc` (client/vmc_sink.cc, client/avatar_levels.cc): a level maps linearly from the setup's
[min, max] to [0, 1], so the three drawings stay three steps (closed 0, mid, open 1)."""

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 39539  # the VMC protocol's performer port
IMMEDIATELY = (0, 1)  # OSC's time tag "immediately" (liblo's LO_TT_IMMEDIATE), as `koma live`


def parse_target(text):
    """"HOST:PORT", "HOST", ":PORT" or "PORT" -> (host, port); the rest from the defaults."""
    if text is None or text == "":
        return DEFAULT_HOST, DEFAULT_PORT
    host, colon, port = text.rpartition(":")
    if not colon:
        host, port = ("", text) if text.isdigit() else (text, "")
    if port and (not port.isdigit() or not 0 < int(port) < 65536):
        raise ValueError(f"--vmc {text}: the port must be a number 1-65535 (HOST:PORT)")
    return host.strip("[]") or DEFAULT_HOST, int(port) if port else DEFAULT_PORT


def levels(mouth_min=None, mouth_max=None, eyes_min=None, eyes_max=None):
    """The (min, max) of the mouth and of the eyes the server uses for these settings
    (LiveLipBlinkSetup): mouth min unset 0, max unset max(1, min + 1); eyes 0 and 1."""
    m0 = 0.0 if mouth_min is None else float(mouth_min)
    m1 = max(1.0, m0 + 1.0) if mouth_max is None else float(mouth_max)
    e0 = 0.0 if eyes_min is None else float(eyes_min)
    e1 = 1.0 if eyes_max is None else float(eyes_max)
    return (m0, m1), (e0, e1)


def _normalised(level, bounds):
    low, high = bounds
    if not high > low:
        return 0.0
    return min(1.0, max(0.0, (float(level) - low) / (high - low)))


class VmcSender:
    """Sends each frame's mouth and blink as VMC blend shapes to host:port (UDP): clips
    mouth_clip ("A"; VRM 1.0 "aa") and blink_clip ("Blink"; VRM 1.0 "blink"); the levels
    mapped from mouth_range and eye_range (levels())."""

    def __init__(self, host=DEFAULT_HOST, port=DEFAULT_PORT, mouth_range=(0.0, 1.0),
                 eye_range=(0.0, 1.0), mouth_clip="A", blink_clip="Blink"):
        try:
            import liblo  # noqa: PLC0415  (only with --vmc)
        except ImportError:
            raise ImportError("--vmc needs liblo's Python module: install the Debian package "
                              "python3-liblo (apt-get install python3-liblo)") from None
        self._liblo = liblo
        self.host, self.port = host, port
        self._address = liblo.Address(host, port, liblo.UDP)
        self.mouth_range, self.eye_range = mouth_range, eye_range
        self.mouth_clip, self.blink_clip = mouth_clip, blink_clip

    def values(self, frame):
        """The frame's (mouth, blink) values: how open the mouth is, 1 - how open the eyes
        are, each 0..1."""
        return (_normalised(frame.mouth_level, self.mouth_range),
                1.0 - _normalised(frame.eye_level, self.eye_range))

    def send(self, frame):
        mouth, blink = self.values(frame)
        liblo = self._liblo
        bundle = liblo.Bundle(
            IMMEDIATELY,
            liblo.Message("/VMC/Ext/Blend/Val", ("s", self.mouth_clip), ("f", mouth)),
            liblo.Message("/VMC/Ext/Blend/Val", ("s", self.blink_clip), ("f", blink)),
            liblo.Message("/VMC/Ext/Blend/Apply"))
        liblo.send(self._address, bundle)
