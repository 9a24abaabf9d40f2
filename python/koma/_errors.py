"""koma.KomaError: what a failed call raises."""
import re

import grpc

_LINE = re.compile(r"\bline (\d+)\b")


class KomaError(Exception):
    """A call the server refused or could not answer.

    Attributes:
        code: the gRPC status code (a grpc.StatusCode, e.g. INVALID_ARGUMENT,
            RESOURCE_EXHAUSTED, DEADLINE_EXCEEDED, UNAVAILABLE).
        message: the server's message, which starts with the request field it is about,
            e.g. "bvh_text: line 12: unknown channel name \"Xrot\" ...".
        field: that field ("bvh_text", "omissions", "curves.curves[2].samples"), or None
            when the message does not start with one.
        line: the file's line number for a parse error of a file ("line 12"), else None.
    """

    def __init__(self, code, message):
        self.code = code
        self.message = message
        head = message.split(": ", 1)[0] if ": " in message else ""
        self.field = head if head and " " not in head else None
        match = _LINE.search(message)
        self.line = int(match.group(1)) if match else None
        super().__init__(f"{code.name}: {message}")

    @classmethod
    def from_rpc_error(cls, error):
        """The KomaError of a grpc.RpcError raised by a stub."""
        code = error.code() if hasattr(error, "code") else grpc.StatusCode.UNKNOWN
        details = error.details() if hasattr(error, "details") else str(error)
        return cls(code, details or "")
