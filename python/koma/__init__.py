"""koma from Python: retime animation into Japanese limited-animation timing.

    import koma
    client = koma.Client("127.0.0.1:50051")
    result = client.retime_skeletal("samples/pitch.bvh", omissions=4, max_hold=3)
    result.write("pitch_anime.bvh")      # the retimed BVH, as `koma skeletal -o` writes it
    print(result.counts, result.timing)  # counts, and {output frame: source frame}

Built from proto/ at build time (stubs by Debian's protoc + grpc_python_plugin) on Debian's
python3-grpcio and python3-protobuf; see docs/python.md.
"""
from koma._version import __version__  # the project's one version, written by the build
from koma._client import Client, Positions
from koma._errors import KomaError
from koma._results import CurvesResult, LipBlinkResult, SkeletalResult
from koma._live import LiveFrame
from koma._live_sources import AudioFile, AudioSourceError, Microphone
from koma._sheet_timing import SheetError

__all__ = ["__version__", "Client", "Positions", "KomaError", "SkeletalResult", "CurvesResult",
           "LipBlinkResult", "LiveFrame", "AudioFile", "Microphone", "AudioSourceError",
           "SheetError"]
