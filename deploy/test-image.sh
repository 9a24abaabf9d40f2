#!/usr/bin/env bash
# Builds deploy/Dockerfile with buildah, runs the image with podman, and checks it end to end:
# health SERVING, the host client retimes the sample through the published loopback port,
# SIGTERM stops it with exit code 0, and it runs as a non-root user; then deploy/k8s's
# Deployment and Service run under `podman kube play` (the pod's restricted security context,
# ready through its gRPC probe, a retime).
# Usage: deploy/test-image.sh KOMA_CLIENT   (the host's `koma` binary)
# Needs root (or rootless podman), buildah, podman, runc and debootstrap: scripts/install-deps.sh.
set -euo pipefail
client=$1
root=$(cd "$(dirname "$0")/.." && pwd)
image=localhost/koma:test
base=docker.io/library/debian:bookworm-slim
container=koma-test-$$
podman_run=(podman run --runtime runc --ulimit nofile=1024:1024 --ulimit nproc=1024:1024)

cleanup() {
  podman rm -f "$container" >/dev/null 2>&1 || true
  podman image prune -f >/dev/null 2>&1 || true  # earlier builds' untagged images
  if [ -n "${rootfs:-}" ]; then rm -rf "$rootfs"; fi
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  podman logs "${logs_of:-$container}" >&2 2>/dev/null || true
  exit 1
}

# The base image: local storage, else a registry, else made here with debootstrap.
if ! podman image exists "$base"; then
  if ! timeout 30 buildah pull --quiet "$base" >/dev/null 2>&1; then
    echo "no registry answers: making $base with debootstrap --variant=minbase bookworm"
    rootfs=$(mktemp -d)
    debootstrap --variant=minbase bookworm "$rootfs" http://deb.debian.org/debian >/dev/null
    working=$(buildah from scratch)
    buildah copy "$working" "$rootfs" / >/dev/null
    buildah config --cmd /bin/bash "$working"
    buildah commit --quiet "$working" "$base" >/dev/null
    buildah rm "$working" >/dev/null
  fi
fi

echo "building $image"
buildah bud --quiet --isolation chroot --format docker -f "$root/deploy/Dockerfile" -t "$image" \
  "$root" >/dev/null

port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"${podman_run[@]}" -d --name "$container" -p "127.0.0.1:$port:50051" "$image" >/dev/null 2>&1 \
  || fail "podman run failed"

for _ in $(seq 60); do
  [ "$("$client" health --server "127.0.0.1:$port" --deadline 1 2>/dev/null)" = SERVING ] && break
  sleep 0.5
done
[ "$("$client" health --server "127.0.0.1:$port")" = SERVING ] || fail "health is not SERVING"

out=$(mktemp -d)
"$client" skeletal "$root/samples/pitch.bvh" -o "$out/pitch.bvh" --server "127.0.0.1:$port" \
  || fail "retiming through the container failed"
grep -q "^Frames: 130" "$out/pitch.bvh" || fail "retimed BVH has the wrong frame count"
rm -rf "$out"

user=$(podman exec "$container" id -u)
[ "$user" != 0 ] || fail "the server runs as root"

podman stop -t 15 "$container" >/dev/null 2>&1
code=$(podman inspect "$container" --format '{{.State.ExitCode}}')
[ "$code" = 0 ] || fail "exit code $code after SIGTERM"
podman logs "$container" 2>&1 | grep -q '"msg":"koma_server stopped"' || fail "no clean stop in the log"

# The Kubernetes manifests (deploy/k8s/deployment.yaml and service.yaml) through
# `podman kube play`: the restricted security context must run, the pod must become ready
# through its gRPC probe and answer a retime. Changed for the test only: the image name; one
# replica; and each containerPort published on 127.0.0.1 at a free port (podman 4.3
# publishes containerPorts on the host's every interface at the same number otherwise).
kube_dir=$(mktemp -d)
/usr/bin/python3 - "$root/deploy/k8s" "$image" "$kube_dir/koma.yaml" <<'PY' || fail "the manifests"
import socket, sys, yaml
k8s, image, out = sys.argv[1:]
docs = [d for name in ("deployment.yaml", "service.yaml")
        for d in yaml.safe_load_all(open(f"{k8s}/{name}")) if d]
deployment = next(d for d in docs if d["kind"] == "Deployment")
deployment["spec"]["replicas"] = 1
container = deployment["spec"]["template"]["spec"]["containers"][0]
container["image"] = image
for port in container["ports"]:
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port["hostIP"], port["hostPort"] = "127.0.0.1", s.getsockname()[1]
    s.close()
yaml.safe_dump_all(docs, open(out, "w"))
PY
# runc and bounded ulimits, as `podman run` above gets them.
printf '[containers]\ndefault_ulimits = ["nofile=1024:1024", "nproc=1024:1024"]\n[engine]\nruntime = "runc"\n' \
  >"$kube_dir/containers.conf"
export CONTAINERS_CONF=$kube_dir/containers.conf
kube_down() { podman kube play --down "$kube_dir/koma.yaml" >/dev/null 2>&1 || true; }
trap 'kube_down; rm -rf "$kube_dir"; cleanup' EXIT
# podman names a Deployment's pods DEPLOYMENT-pod-N and their containers POD-NAME.
kube_container=koma-pod-0-koma
logs_of=$kube_container
podman kube play "$kube_dir/koma.yaml" >"$kube_dir/play.log" 2>&1 ||
  fail "podman kube play: $(cat "$kube_dir/play.log")"
read -r probe_port grpc_host_port < <(/usr/bin/python3 -c 'import sys, yaml
doc = next(d for d in yaml.safe_load_all(open(sys.argv[1])) if d and d["kind"] == "Deployment")
c = doc["spec"]["template"]["spec"]["containers"][0]
port = c["readinessProbe"]["grpc"]["port"]
print(port, next(p["hostPort"] for p in c["ports"] if p["containerPort"] == port))' \
  "$kube_dir/koma.yaml")
# The kubelet's grpc probe (podman 4.3 does not run grpc probes): grpc.health.v1 Check on the
# probe's port inside the pod.
ready=""
for _ in $(seq 60); do
  if [ "$(podman exec "$kube_container" /usr/local/bin/koma health --server "127.0.0.1:$probe_port" \
          --deadline 1 2>/dev/null)" = SERVING ]; then ready=1; break; fi
  sleep 0.5
done
[ -n "$ready" ] || fail "the kube-play pod never became ready (gRPC probe on port $probe_port)"
[ "$(podman exec "$kube_container" /usr/bin/id -u)" = 10001 ] || fail "the kube-play pod does not run as 10001"
status=$(podman exec "$kube_container" /bin/cat /proc/1/status)
grep -q '^CapEff:[[:space:]]*0*$' <<<"$status" ||
  fail "the kube-play pod keeps capabilities: $(grep Cap <<<"$status")"
grep -q '^Seccomp:[[:space:]]*2$' <<<"$status" || fail "the kube-play pod has no seccomp filter"
grep -q '^NoNewPrivs:[[:space:]]*1$' <<<"$status" || fail "the kube-play pod allows privilege escalation"
out=$(mktemp -d)
"$client" skeletal "$root/samples/pitch.bvh" -o "$out/pitch.bvh" \
  --server "127.0.0.1:$grpc_host_port" >/dev/null ||
  { rm -rf "$out"; fail "retiming through the kube-play pod failed"; }
grep -q "^Frames: 130" "$out/pitch.bvh" || { rm -rf "$out"; fail "kube-play retime: wrong frames"; }
rm -rf "$out"
echo "PASS: image builds, serves, retimes, runs as uid $user, stops cleanly; the Kubernetes" \
  "manifests run under podman kube play (restricted: uid 10001, no capabilities, seccomp," \
  "no new privileges), ready through the gRPC probe, and retime"
