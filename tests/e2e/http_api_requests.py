"""Helpers of http_api_e2e_test.sh: the sample requests, gRPC's raw answer, and JSON against
binary. Usage (PYTHONPATH: the built koma package):
  http_api_requests.py make SAMPLES_DIR OUT_DIR   OUT_DIR/<Rpc>.bin and <Rpc>.json per RPC
  http_api_requests.py grpc TARGET RPC IN OUT      the raw gRPC answer to IN's bytes, to OUT
  http_api_requests.py same RPC JSON_ANSWER BIN    exit 0 when the JSON answer parses to BIN
"""
import os
import sys

import grpc
from google.protobuf import json_format

from koma.v1 import retime_pb2 as pb

RESPONSES = {'RetimeSkeletal': pb.RetimeSkeletalResponse, 'RetimeCurves': pb.RetimeCurvesResponse,
             'LipBlink': pb.LipBlinkResponse}


def make(samples, out):
    def read(name):
        return open(os.path.join(samples, name), 'rb').read()
    requests = {
        'RetimeSkeletal': pb.RetimeSkeletalRequest(bvh_text=read('pitch.bvh')),
        'RetimeCurves': pb.RetimeCurvesRequest(motion3_json=read('arm_head.motion3.json')),
        'LipBlink': pb.LipBlinkRequest(audio=read('voice.flac')),
    }
    for rpc, request in requests.items():
        open(os.path.join(out, rpc + '.bin'), 'wb').write(request.SerializeToString())
        open(os.path.join(out, rpc + '.json'), 'w').write(json_format.MessageToJson(request))


def raw_grpc(target, rpc, path_in, path_out):
    call = grpc.insecure_channel(target).unary_unary('/koma.v1.Retime/' + rpc)
    answer = call(open(path_in, 'rb').read(), timeout=60)  # no serializers: bytes as they are
    open(path_out, 'wb').write(answer)


def same(rpc, json_answer, binary_answer):
    from_json = json_format.Parse(open(json_answer).read(), RESPONSES[rpc]())
    from_binary = RESPONSES[rpc].FromString(open(binary_answer, 'rb').read())
    if from_json != from_binary:
        sys.exit('%s: the JSON answer is not the binary answer' % rpc)


if __name__ == '__main__':
    {'make': make, 'grpc': raw_grpc, 'same': same}[sys.argv[1]](*sys.argv[2:])
