"""Live frames to a VMC-protocol receiver (VSeeFace, VNyan, Warudo, ...): per frame one OSC
bundle over UDP of
    /VMC/Ext/Blend/Val "A" <mouth level, 0..1>
    /VMC/Ext/Blend/Val "Blink" <1 - eye openness, 0..1>
    /VMC/Ext/Blend/Apply
through liblo (Debian package python3-liblo), imported only here."""

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 39539  # the VMC protocol's performer port


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


def _clamp(value):
    return min(1.0, max(0.0, float(value)))


class VmcSender:
    """Sends each frame's mouth and blink as VMC blend shapes to host:port (UDP)."""

    def __init__(self, host=DEFAULT_HOST, port=DEFAULT_PORT):
        try:
            import liblo  # noqa: PLC0415  (only with --vmc)
        except ImportError:
            raise ImportError("--vmc needs liblo's Python module: install the Debian package "
                              "python3-liblo (apt-get install python3-liblo)") from None
        self._liblo = liblo
        self.host, self.port = host, port
        self._address = liblo.Address(host, port, liblo.UDP)

    def values(self, frame):
        """The frame's (A, Blink): the mouth level and 1 - the eye level, each within 0..1."""
        return _clamp(frame.mouth_level), _clamp(1.0 - frame.eye_level)

    def send(self, frame):
        mouth, blink = self.values(frame)
        liblo = self._liblo
        bundle = liblo.Bundle(
            liblo.Message("/VMC/Ext/Blend/Val", ("s", "A"), ("f", mouth)),
            liblo.Message("/VMC/Ext/Blend/Val", ("s", "Blink"), ("f", blink)),
            liblo.Message("/VMC/Ext/Blend/Apply"))
        liblo.send(self._address, bundle)
