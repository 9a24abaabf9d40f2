"""Checks deploy/k8s, deploy/nginx and deploy/Dockerfile against each other and against
koma_server's flags.

Usage: manifests_test.py DEPLOY_DIR KOMA_SERVER. Prints "N passed, N failed"; exit 1 on any
failure.
"""
import re
import subprocess
import sys

import yaml

deploy, server = sys.argv[1], sys.argv[2]
checks = []


def check(name, ok, detail=""):
    checks.append(ok)
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + detail))


def load(path):
    with open(f"{deploy}/{path}") as f:
        return [doc for doc in yaml.safe_load_all(f) if doc]


docs = load("k8s/deployment.yaml") + load("k8s/service.yaml") + load("k8s/autoscaling.yaml")
by_kind = {}
for doc in docs:
    by_kind.setdefault(doc["kind"], []).append(doc)
check("every manifest has apiVersion, kind and metadata.name",
      all("apiVersion" in d and d["metadata"].get("name") for d in docs))

deployment = by_kind["Deployment"][0]
pod = deployment["spec"]["template"]
container = pod["spec"]["containers"][0]
args = dict(a[2:].split("=", 1) for a in container["args"])

# Every flag in the manifest is a real koma_server flag.
help_text = subprocess.run([server, "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True).stdout
known = set(re.findall(r"^\s+--(\w+)", help_text, re.M))
check("koma_server --help lists its flags", len(known) >= 8, str(known))
for flag in args:
    check(f"--{flag} is a koma_server flag", flag in known, f"known: {sorted(known)}")

port = int(args["address"].rsplit(":", 1)[1])
check("listens on all interfaces in the pod", args["address"].startswith("0.0.0.0:"))
check("containerPort matches --address",
      container["ports"][0]["containerPort"] == port, str(container["ports"]))
for probe in ("readinessProbe", "livenessProbe"):
    check(f"{probe} asks grpc.health.v1 on the server port",
          container[probe].get("grpc", {}).get("port") == port, str(container[probe]))

grace_s = pod["spec"]["terminationGracePeriodSeconds"]
drain_s = (int(args["shutdown_delay_ms"]) + int(args["shutdown_grace_ms"])) / 1000
pre_stop = container["lifecycle"]["preStop"]["exec"]["command"]
pre_stop_s = int(pre_stop[-1]) if pre_stop[0].endswith("sleep") else 0
check("terminationGracePeriodSeconds covers preStop + the delay and drain",
      grace_s > pre_stop_s + drain_s, f"{grace_s} <= {pre_stop_s} + {drain_s}")
check("CPU sized for 2 cores", str(container["resources"]["limits"]["cpu"]) == "2" and
      args.get("worker_threads") == "2")
check("runs as the image's non-root uid", pod["spec"]["securityContext"]["runAsUser"] == 10001)

labels = pod["metadata"]["labels"]
for service in by_kind["Service"]:
    check(f"Service {service['metadata']['name']} selects the pods",
          service["spec"]["selector"].items() <= labels.items())
    check(f"Service {service['metadata']['name']} targets the grpc port",
          service["spec"]["ports"][0]["targetPort"] in ("grpc", port))
check("one headless Service for client-side balancing",
      sum(s["spec"].get("clusterIP") == "None" for s in by_kind["Service"]) == 1)

# Prometheus metrics: off by default in the binary (--help), on in the pod and the image,
# on the same port everywhere.
help_metrics = re.search(r"--metrics_address \((.*?)\); default: \"(.*?)\";", help_text, re.S)
check("--help lists --metrics_address, off by default",
      help_metrics is not None and help_metrics.group(2) == "", str(help_metrics))
suggested = re.search(r"0\.0\.0\.0:(\d+)", help_metrics.group(1)) if help_metrics else None
metrics_port = int(args.get("metrics_address", ":0").rsplit(":", 1)[1])
check("the pod serves metrics on the port --help suggests for containers",
      suggested is not None and metrics_port == int(suggested.group(1)) and
      args["metrics_address"].startswith("0.0.0.0:"), args.get("metrics_address", "unset"))
named = {p.get("name"): p["containerPort"] for p in container["ports"]}
check("containerPort \"metrics\" matches --metrics_address",
      named.get("metrics") == metrics_port and metrics_port != port, str(container["ports"]))
annotations = pod["metadata"].get("annotations", {})
check("prometheus.io annotations scrape /metrics on the metrics port",
      annotations.get("prometheus.io/scrape") == "true" and
      annotations.get("prometheus.io/port") == str(metrics_port) and
      annotations.get("prometheus.io/path") == "/metrics", str(annotations))

with open(f"{deploy}/Dockerfile") as f:
    dockerfile = f.read()
runtime = dockerfile.rsplit("\nFROM ", 1)[-1]  # the last stage is what runs
image_metrics = re.search(r"^ENV KOMA_METRICS_ADDRESS=(\S+):(\d+)$", runtime, re.M)
exposed = {int(p) for line in re.findall(r"^EXPOSE (.+)$", runtime, re.M) for p in line.split()}
check("the image serves metrics on all interfaces on the pod's metrics port",
      image_metrics is not None and image_metrics.group(1) == "0.0.0.0" and
      int(image_metrics.group(2)) == metrics_port, str(image_metrics))
check("the image EXPOSEs the gRPC and metrics ports", {port, metrics_port} <= exposed,
      str(exposed))
check("the image installs prometheus-cpp's runtime libraries",
      all(lib in runtime for lib in ("libprometheus-cpp-core1.0", "libprometheus-cpp-pull1.0",
                                      "libcivetweb1")))

hpa = by_kind["HorizontalPodAutoscaler"][0]
check("HPA scales the Deployment",
      hpa["spec"]["scaleTargetRef"]["name"] == deployment["metadata"]["name"])
pdb = by_kind["PodDisruptionBudget"][0]
check("PDB selects the pods", pdb["spec"]["selector"]["matchLabels"].items() <= labels.items())

max_message = int(args["max_message_bytes"])
with open(f"{deploy}/nginx/koma.conf") as f:
    nginx = f.read()
body = re.search(r"client_max_body_size\s+(\d+)m;", nginx)
check("nginx client_max_body_size matches --max_message_bytes",
      body is not None and int(body.group(1)) * 1024 * 1024 == max_message,
      body.group(0) if body else "missing")
check("nginx passes gRPC and keeps upstream connections",
      "grpc_pass grpc://" in nginx and re.search(r"keepalive\s+\d+;", nginx) is not None)

failed = checks.count(False)
print(f"{len(checks) - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
