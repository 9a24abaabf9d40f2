"""A second, independent client: Debian's python3-grpcio against the real koma_server.

Usage: python_client.py PORT GENERATED_DIR, where GENERATED_DIR holds `protoc --python_out`
output for proto/. Exits non-zero (with an AssertionError) on any mismatch.
"""
import sys

import grpc

port, generated = sys.argv[1], sys.argv[2]
sys.path.insert(0, generated)
from koma.v1 import retime_pb2  # noqa: E402  (generated at test time)

MAX_MESSAGE = 256 << 20
channel = grpc.insecure_channel(
    f"127.0.0.1:{port}",
    options=[("grpc.max_receive_message_length", MAX_MESSAGE),
             ("grpc.max_send_message_length", MAX_MESSAGE)])
retime = channel.unary_unary(
    "/koma.v1.Retime/RetimeSkeletal",
    request_serializer=retime_pb2.RetimeSkeletalRequest.SerializeToString,
    response_deserializer=retime_pb2.RetimeSkeletalResponse.FromString)


def make_request(frames):
    request = retime_pb2.RetimeSkeletalRequest()
    motion = request.motion
    root = motion.skeleton.joints.add(name="Hips", parent=-1)
    root.channels.extend(["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation",
                          "Yrotation"])
    arm = motion.skeleton.joints.add(name="Arm", parent=0)
    arm.offset.y = 10.0
    arm.channels.extend(["Zrotation"])
    arm.end_sites.add(y=5.0)
    motion.frame_time = 1.0 / 24.0
    motion.frame_count = frames
    for f in range(frames):
        s = f / (frames - 1)
        eased = s * s * (3 - 2 * s)  # slow, fast, slow
        # The root turns, so the arm joint swings around it.
        motion.channels.values.extend([0, 0, 0, 120 * eased, 0, 0, 0])
    return request


# A good call: the fastest frames go, the length stays, frames are verbatim copies.
request = make_request(48)
request.omissions = 3
response = retime(request, timeout=10)
assert len(response.source_frames) == 48, len(response.source_frames)
assert response.source_frames[0] == 0 and response.source_frames[-1] == 47
assert response.omissions_applied == 3, response.omissions_applied
assert all(20 <= f <= 27 for f in response.deleted_frames), list(response.deleted_frames)
values = response.motion.channels.values
for t, source in enumerate(response.source_frames):
    assert values[7 * t + 3] == request.motion.channels.values[7 * source + 3]
assert response.motion.frame_time == 1.0 / 24.0  # returned unchanged, bit for bit

# A bad call: the code and the field path reach a Python caller intact.
bad = make_request(10)
bad.motion.channels.values[13] = float("nan")
try:
    retime(bad, timeout=10)
    raise AssertionError("a NaN value was accepted")
except grpc.RpcError as error:
    assert error.code() == grpc.StatusCode.INVALID_ARGUMENT, error.code()
    assert "motion.channels.values[13]: nan" in error.details(), error.details()

print("PASS: python3-grpcio client")
