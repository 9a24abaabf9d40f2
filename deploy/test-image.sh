#!/usr/bin/env bash
# Builds deploy/Dockerfile with buildah, runs the image with podman, and checks it end to end:
# health SERVING, the host client retimes the sample through the published loopback port,
# SIGTERM stops it with exit code 0, and it runs as a non-root user.
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
fail() { echo "FAIL: $*" >&2; podman logs "$container" >&2 2>/dev/null || true; exit 1; }

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
echo "PASS: image builds, serves, retimes, runs as uid $user, stops cleanly"
