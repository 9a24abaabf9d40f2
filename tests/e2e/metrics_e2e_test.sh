#!/usr/bin/env bash
# End to end: the real koma_server with its Prometheus endpoint on a free loopback port, the
# real koma client a known number of times, then GET /metrics over HTTP: exact counts per
# method and code, histogram counts, frames, bytes (against the server's own JSON log), the
# in-flight gauge back at 0, and every line valid text exposition format.
# Usage: metrics_e2e_test.sh KOMA_SERVER KOMA PYTHON3 PITCH_BVH CURVES_MOTION3 LIPBLINK_MOTION3
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 pitch=$4 curves_sample=$5 lip_sample=$6

source "$(dirname "$0")/lib.sh"

# A bad --metrics_address: exit 1, the flag and the value named, no crash (bounded by timeout).
check_refused '--metrics_address: "nonsense" is not HOST:PORT' "$server_bin" \
  --metrics_address=nonsense
check_refused '--metrics_address: "127.0.0.1:70000"' "$server_bin" \
  --metrics_address=127.0.0.1:70000
check_refused '--metrics_port_file needs --metrics_address' "$server_bin" \
  --metrics_port_file="$work/x"

# The address from the environment (as in the container), the port file from a flag. Pitch
# has 20 joints; --max_joints=30 lets a 31-joint clip be RESOURCE_EXHAUSTED.
KOMA_LOG_FORMAT=json KOMA_METRICS_ADDRESS=127.0.0.1:0 start_server "$server_bin" \
  --metrics_port_file="$work/metrics_port" --max_joints=30 --worker_threads=2
metrics_port=$(cat "$work/metrics_port")
[ "$metrics_port" -gt 0 ] || fail "metrics port file holds '$metrics_port'"
metrics_url="http://127.0.0.1:$metrics_port/metrics"

# The port is taken now: a second server must refuse it.
check_refused "--metrics_address: could not listen on 127.0.0.1:$metrics_port" "$server_bin" \
  --metrics_address="127.0.0.1:$metrics_port"

expect_code() {  # expect_code CODE COMMAND...: the client fails with gRPC code CODE
  local want=$1
  shift
  expect_error 1 "koma: $want: " "$@" >/dev/null
}

# RetimeSkeletal: 3 OK, 1 OUT_OF_RANGE, 1 RESOURCE_EXHAUSTED.
for i in 1 2 3; do
  "$client_bin" skeletal "$pitch" -o "$work/pitch$i.bvh" --server "$target" --deadline 30 \
    >/dev/null || fail "koma skeletal $i failed"
done
expect_code OUT_OF_RANGE "$client_bin" skeletal "$pitch" -o "$work/bad.bvh" --omit 500 \
  --server "$target"
"$python" - "$work/big.bvh" <<'PY'
import sys
joints = 31  # one more than --max_joints
lines = ["HIERARCHY", "ROOT J0", "{", "OFFSET 0 0 0", "CHANNELS 3 Xposition Yposition Zposition"]
for j in range(1, joints):
    lines += [f"JOINT J{j}", "{", "OFFSET 0 1 0", "CHANNELS 1 Zrotation"]
lines += ["End Site", "{", "OFFSET 0 1 0", "}"] + ["}"] * joints
lines += ["MOTION", "Frames: 3", "Frame Time: 0.0416667"]
lines += [" ".join(["0"] * (3 + joints - 1))] * 3
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
PY
expect_code RESOURCE_EXHAUSTED "$client_bin" skeletal "$work/big.bvh" -o "$work/big_out.bvh" \
  --server "$target"

# RetimeCurves: 1 OK. LipBlink: 1 OK, 1 INVALID_ARGUMENT.
"$client_bin" curves "$curves_sample" -o "$work/curves.motion3.json" --server "$target" \
  >"$work/curves.txt" || fail "koma curves failed"
"$client_bin" lipblink "$lip_sample" -o "$work/lip.motion3.json" --server "$target" \
  >"$work/lip.txt" || fail "koma lipblink failed"
expect_code INVALID_ARGUMENT "$client_bin" lipblink "$lip_sample" -o "$work/bad.motion3.json" \
  --mouth ParamMouth --server "$target"

# Frames as the client reports them ("...: 5 curves, 91 frames at 30 fps").
pitch_frames=$(sed -n 's/^Frames:[[:space:]]*//p' "$pitch" | tr -d '\r')
curves_frames=$(sed -n 's/.* \([0-9]*\) frames at .*/\1/p' "$work/curves.txt" | head -1)
lip_frames=$(sed -n 's/.* \([0-9]*\) frames at .*/\1/p' "$work/lip.txt" | head -1)
[ -n "$curves_frames" ] && [ -n "$lip_frames" ] || fail "no frame counts in the summaries"

# Scrape once while serving; check after the stop, against the complete log.
"$python" - "$metrics_url" "$work/metrics.txt" <<'PY' || fail "GET /metrics failed"
import sys, urllib.request
with urllib.request.urlopen(sys.argv[1], timeout=10) as r:
    assert r.status == 200, r.status
    assert r.headers["Content-Type"].startswith("text/plain"), r.headers["Content-Type"]
    open(sys.argv[2], "wb").write(r.read())
PY
stop_server

server_version=$("$server_bin" --version | sed -n 's/^koma_server //p')
[ -n "$server_version" ] || fail "koma_server --version printed no version"
"$python" - "$work/metrics.txt" "$work/server.log" "$pitch_frames" "$curves_frames" \
  "$lip_frames" "$server_version" <<'PY' || fail "the scraped metrics are wrong (above)"
import collections, json, math, re, sys

text = open(sys.argv[1]).read()
pitch_frames, curves_frames, lip_frames = map(int, sys.argv[3:6])

# 1. Every line is valid text exposition format (version 0.0.4).
name_re = r"[a-zA-Z_:][a-zA-Z0-9_:]*"
sample_re = re.compile(rf"^({name_re})(?:\{{(.*)\}})? (\S+)(?: -?\d+)?$")
label_re = re.compile(r'([a-zA-Z_][a-zA-Z0-9_]*)="((?:[^"\\\n]|\\[\\"n])*)"(,|$)')
types, samples = {}, collections.defaultdict(float)
assert text.endswith("\n"), "no final newline"
for n, line in enumerate(text.splitlines(), 1):
    where = f"line {n}: {line!r}"
    if line.startswith("#"):
        m = re.match(rf"^# (HELP|TYPE) ({name_re}) (.*)$", line)
        assert m, where
        if m[1] == "TYPE":
            assert m[3] in ("counter", "gauge", "histogram", "summary", "untyped"), where
            assert m[2] not in types, "TYPE twice: " + where
            types[m[2]] = m[3]
        continue
    m = sample_re.match(line)
    assert m, where
    name, label_text, value = m[1], m[2] or "", m[3]
    labels, pos = [], 0
    while pos < len(label_text):
        lm = label_re.match(label_text, pos)
        assert lm, where
        labels.append((lm[1], lm[2]))
        pos = lm.end()
    v = float(value)  # accepts NaN, +Inf, -Inf too
    # A histogram's _bucket/_count/_sum and a summary's _count/_sum share its TYPE line.
    suffix = re.search(r"_(bucket|count|sum)$", name)
    base_type = types.get(name[:suffix.start()]) if suffix else None
    assert (types.get(name) or base_type == "histogram" or
            (base_type == "summary" and suffix[1] != "bucket")), "sample before its TYPE: " + where
    if types.get(name) == "counter":
        assert name.endswith("_total") and v >= 0 and not math.isnan(v), where
    samples[(name, frozenset(labels))] = v

def value(name, **labels):
    want = set(labels.items())
    hits = [v for (n, ls), v in samples.items() if n == name and want <= set(ls)]
    assert len(hits) == 1, (name, labels, hits)
    return hits[0]

# 2. Exact counts. Expected calls per method and code (everything else 0).
expected = {
    "RetimeSkeletal": {"OK": 3, "OUT_OF_RANGE": 1, "RESOURCE_EXHAUSTED": 1},
    "RetimeCurves": {"OK": 1},
    "LipBlink": {"OK": 1, "INVALID_ARGUMENT": 1},
}
codes = ["OK", "CANCELLED", "UNKNOWN", "INVALID_ARGUMENT", "DEADLINE_EXCEEDED", "NOT_FOUND",
         "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
         "ABORTED", "OUT_OF_RANGE", "UNIMPLEMENTED", "INTERNAL", "UNAVAILABLE", "DATA_LOSS",
         "UNAUTHENTICATED"]
frames = {"RetimeSkeletal": 3 * pitch_frames, "RetimeCurves": curves_frames,
          "LipBlink": lip_frames}
rpcs = [r for r in map(json.loads, open(sys.argv[2])) if r.get("msg") == "rpc"]
assert len(rpcs) == 8, len(rpcs)
for method, by_code in expected.items():
    grpc = dict(grpc_type="unary", grpc_service="koma.v1.Retime", grpc_method=method)
    calls = sum(by_code.values())
    assert value("grpc_server_started_total", **grpc) == calls, method
    for code in codes:
        got = value("grpc_server_handled_total", grpc_code=code, **grpc)
        assert got == by_code.get(code, 0), (method, code, got)
    assert value("grpc_server_handling_seconds_count", **grpc) == calls, method
    assert value("grpc_server_handling_seconds_bucket", le="+Inf", **grpc) == calls, method
    assert 0 < value("grpc_server_handling_seconds_sum", **grpc) < 60, method
    buckets = sorted((float(dict(ls)["le"]), v) for (n, ls), v in samples.items()
                     if n == "grpc_server_handling_seconds_bucket" and dict(ls)["grpc_method"] == method)
    assert len(buckets) == 16 and buckets[0][0] == 0.0005 and buckets[-2][0] == 30, buckets
    assert all(a[1] <= b[1] for a, b in zip(buckets, buckets[1:])), ("not cumulative", buckets)
    assert value("koma_frames_processed_total", grpc_method=method) == frames[method], method
    # Bytes: the log's per-call sizes, summed (responses only from OK calls).
    mine = [r for r in rpcs if r["method"] == method]
    assert len(mine) == calls, (method, mine)
    assert value("koma_request_bytes_total", grpc_method=method) == sum(r["bytes_in"] for r in mine)
    assert value("koma_response_bytes_total", grpc_method=method) == sum(
        r["bytes_out"] for r in mine if r["code"] == "OK") > 0
assert value("koma_requests_in_flight") == 0
# The build: one koma_build_info series, its version that of koma_server --version.
assert value("koma_build_info", version=sys.argv[6]) == 1, sys.argv[6]
for name, kind in [("grpc_server_started_total", "counter"),
                   ("grpc_server_handled_total", "counter"),
                   ("grpc_server_handling_seconds", "histogram"),
                   ("koma_frames_processed_total", "counter"), ("koma_request_bytes_total", "counter"),
                   ("koma_response_bytes_total", "counter"), ("koma_requests_in_flight", "gauge"),
                   ("koma_build_info", "gauge")]:
    assert types.get(name) == kind, (name, types.get(name))
print(f"metrics: {len(samples)} samples, {len(types)} families, all checks passed")
PY
echo "PASS: metrics end to end"
