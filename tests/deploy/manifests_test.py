"""Checks deploy/k8s, deploy/nginx and deploy/Dockerfile against each other and against
koma_server's flags.

Usage: manifests_test.py DEPLOY_DIR KOMA_SERVER [KOMA]. Prints "N passed, N failed"; exit 1 on
any failure. Also: every pod template against the "restricted" Pod Security Standard, and the
render-farm Indexed Job (deploy/k8s/farm) against `koma batch --help`.
"""
import copy
import re
import subprocess
import sys

import yaml

deploy, server = sys.argv[1], sys.argv[2]
client = sys.argv[3] if len(sys.argv) > 3 else None  # koma: the batch Job's options
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

# The "restricted" Pod Security Standard (kubernetes.io/docs/concepts/security/
# pod-security-standards), on every pod template: what a namespace labelled
# pod-security.kubernetes.io/enforce=restricted admits.
RESTRICTED_VOLUMES = {"configMap", "csi", "downwardAPI", "emptyDir", "ephemeral",
                      "persistentVolumeClaim", "projected", "secret"}


def restricted_violations(spec):
    """The rules of the restricted profile (and the baseline it includes) `spec` breaks."""
    found = []
    pod_context = spec.get("securityContext") or {}
    for key in ("hostNetwork", "hostPID", "hostIPC"):
        if spec.get(key):
            found.append(f"{key}: true")
    for volume in spec.get("volumes") or []:
        kinds = set(volume) - {"name"}
        if not kinds <= RESTRICTED_VOLUMES:
            found.append(f"volume {volume['name']}: {sorted(kinds)} not allowed")
    if pod_context.get("sysctls"):
        found.append("sysctls set")
    containers = (spec.get("initContainers") or []) + spec["containers"]
    for c in containers:
        context = c.get("securityContext") or {}
        name = c["name"]
        if context.get("privileged"):
            found.append(f"{name}: privileged")
        if context.get("allowPrivilegeEscalation") is not False:
            found.append(f"{name}: allowPrivilegeEscalation is not false")
        non_root = context.get("runAsNonRoot", pod_context.get("runAsNonRoot"))
        if non_root is not True:
            found.append(f"{name}: runAsNonRoot is not true")
        if context.get("runAsUser", pod_context.get("runAsUser")) == 0:
            found.append(f"{name}: runAsUser 0")
        seccomp = (context.get("seccompProfile") or pod_context.get("seccompProfile") or {})
        if seccomp.get("type") not in ("RuntimeDefault", "Localhost"):
            found.append(f"{name}: seccompProfile.type is {seccomp.get('type')}, not "
                         "RuntimeDefault or Localhost")
        capabilities = context.get("capabilities") or {}
        if "ALL" not in (capabilities.get("drop") or []):
            found.append(f"{name}: capabilities.drop lacks ALL")
        if set(capabilities.get("add") or []) - {"NET_BIND_SERVICE"}:
            found.append(f"{name}: capabilities.add {capabilities['add']}")
        for port in c.get("ports") or []:
            if port.get("hostPort"):
                found.append(f"{name}: hostPort {port['hostPort']}")
        if context.get("procMount", "Default") != "Default":
            found.append(f"{name}: procMount {context['procMount']}")
    return found


farm_docs = load("k8s/farm/batch-indexed-job.yaml")
for doc in docs + farm_docs:
    template = doc.get("spec", {}).get("template")
    if template:
        problems = restricted_violations(template["spec"])
        check(f"{doc['kind']} {doc['metadata']['name']} meets the restricted Pod Security "
              "Standard", not problems, "; ".join(problems))

# The checker can fail: the Deployment as it was before (no seccomp profile, capabilities
# kept) and a privileged host-path pod break the rules it should name.
weakened = copy.deepcopy(pod["spec"])
del weakened["securityContext"]["seccompProfile"]
del weakened["containers"][0]["securityContext"]["capabilities"]
check("the restricted check names a missing seccomp profile and kept capabilities",
      restricted_violations(weakened) == [
          "koma: seccompProfile.type is None, not RuntimeDefault or Localhost",
          "koma: capabilities.drop lacks ALL"], str(restricted_violations(weakened)))
weakened["hostNetwork"] = True
weakened["volumes"] = [{"name": "host", "hostPath": {"path": "/"}}]
weakened["containers"][0]["securityContext"]["privileged"] = True
check("the restricted check names host networking, host paths and privileged containers",
      {"hostNetwork: true", "volume host: ['hostPath'] not allowed", "koma: privileged"} <=
      set(restricted_violations(weakened)), str(restricted_violations(weakened)))

# The render-farm Indexed Job (docs/operations.md, "On a render farm"): N pods, each task
# K of N through --shard-from-env; the koma client of the image; the headless Service.
job = farm_docs[0]
job_spec = job["spec"]
job_container = job_spec["template"]["spec"]["containers"][0]
env = {e["name"]: e.get("value") for e in job_container.get("env", [])}
check("the batch Job is Indexed", job_spec.get("completionMode") == "Indexed")
check("KOMA_SHARD_COUNT equals completions",
      env.get("KOMA_SHARD_COUNT") == str(job_spec["completions"]), f"{env} {job_spec}")
check("the batch Job runs koma batch --shard-from-env",
      job_container["command"] == ["/usr/local/bin/koma"] and
      job_container["args"][:1] == ["batch"] and "--shard-from-env" in job_container["args"],
      str(job_container))
check("the image has the koma client the Job runs",
      re.search(r"^COPY .* /usr/local/bin/koma$", runtime, re.M) is not None)
headless = [svc for svc in by_kind["Service"] if svc["spec"].get("clusterIP") == "None"][0]
check("the batch Job calls the headless Service on its port",
      f"dns:///{headless['metadata']['name']}:{headless['spec']['ports'][0]['port']}" in
      job_container["args"], str(job_container["args"]))
mounts = {m["mountPath"] for m in job_container["volumeMounts"]}
paths = [a for a in job_container["args"] if a.startswith("/")]
check("the batch Job's inputs, outputs and summary are on its volume",
      paths and all(any(p == m or p.startswith(m + "/") for m in mounts) for p in paths),
      f"{paths} {mounts}")
if client is not None:
    batch_help = subprocess.run([client, "batch", job_container["args"][1], "--help"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
    for arg in job_container["args"]:
        if arg.startswith("-"):
            check(f"koma batch {job_container['args'][1]} has the Job's option {arg}",
                  re.search(r"(^|[\s,])" + re.escape(arg) + r"\b", batch_help) is not None,
                  batch_help[:300])

failed = checks.count(False)
print(f"{len(checks) - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
