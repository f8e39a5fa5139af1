#!/usr/bin/python3
"""YAML side of tests/deploy/check_deploy.sh (stdlib + python3-yaml only).

  deploy_yaml.py lint REPO                  parse every YAML under deploy/ and check the
                                            Kubernetes manifests and the compose file
  deploy_yaml.py compose-env REPO SERVICE ENVFILE [KEY=VALUE...]
                                            shell lines: `export K=V` for the service's
                                            environment (interpolated with ENVFILE, then
                                            the KEY=VALUE overrides) and GF_COMMAND=(...)
  deploy_yaml.py compose-health REPO SERVICE
                                            the healthcheck command, one word per line

Exit 0 if fine, 1 with one line per problem.
"""

import os
import re
import shlex
import sys

import yaml

K8S_NEEDS = ("apiVersion", "kind", "metadata")


def load_all(path):
    with open(path) as f:
        return [d for d in yaml.safe_load_all(f) if d is not None]


def yaml_files(repo):
    for root, _, files in os.walk(os.path.join(repo, "deploy")):
        for name in sorted(files):
            if name.endswith((".yaml", ".yml")):
                yield os.path.join(root, name)


def seconds(text):
    m = re.fullmatch(r"(\d+)(ms|s|m|h)?", str(text))
    if not m:
        return None
    n = int(m.group(1))
    return {"ms": n / 1000, "s": n, None: n, "m": 60 * n, "h": 3600 * n}[m.group(2)]


def interpolate(value, env):
    """Compose's ${VAR}, ${VAR:-default}, ${VAR-default}, ${VAR:?err}, ${VAR?err}."""

    def sub(m):
        name, op, arg = m.group(1), m.group(2), m.group(3) or ""
        v = env.get(name)
        if op in (":-", "-"):
            return v if (v if op == ":-" else v is not None) else arg
        if op in (":?", "?"):
            if (op == ":?" and not v) or v is None:
                raise ValueError(f"${{{name}}} is required: {arg}")
            return v
        return v or ""

    return re.sub(r"\$\{([A-Za-z_][A-Za-z0-9_]*)(?:(:?[-?])([^}]*))?\}", sub, str(value))


def env_dict(service):
    env = service.get("environment") or {}
    if isinstance(env, list):
        env = dict(item.split("=", 1) for item in env)
    return env


def check_k8s(path, docs, problems, base=None):
    kinds = {}
    for i, d in enumerate(docs):
        where = f"{path} (document {i + 1})"
        if os.path.basename(path) == "kustomization.yaml":
            for r in d.get("resources", []):
                if not os.path.exists(os.path.join(base or os.path.dirname(path), r)):
                    problems.append(f"{where}: resource {r} does not exist")
            continue
        for key in K8S_NEEDS:
            if key not in d:
                problems.append(f"{where}: no '{key}'")
        if "name" not in (d.get("metadata") or {}):
            problems.append(f"{where}: no metadata.name")
        kinds.setdefault(d.get("kind"), []).append(d)
    for sts in kinds.get("StatefulSet", []):
        spec = sts["spec"]
        if spec.get("replicas", 1) != 1:
            problems.append(f"{path}: the coordinator StatefulSet must have exactly 1 replica")
        if not spec.get("volumeClaimTemplates"):
            problems.append(f"{path}: StatefulSet without volumeClaimTemplates")
        c = spec["template"]["spec"]["containers"][0]
        for probe in ("readinessProbe", "livenessProbe"):
            if "grpc" not in (c.get(probe) or {}):
                problems.append(f"{path}: coordinator {probe} is not a native gRPC probe")
    for dep in kinds.get("Deployment", []):
        pod = dep["spec"]["template"]["spec"]
        if (pod.get("terminationGracePeriodSeconds") or 30) < 120:
            problems.append(f"{path}: worker terminationGracePeriodSeconds < 120")
    for hpa in kinds.get("HorizontalPodAutoscaler", []):
        names = [m.get("external", {}).get("metric", {}).get("name") for m in hpa["spec"].get("metrics", [])]
        if "gaitforge_queue_depth" not in names:
            problems.append(f"{path}: the HPA does not scale on gaitforge_queue_depth")


def check_compose(path, doc, problems):
    services = doc.get("services") or {}
    for name in ("coordinator", "worker"):
        if name not in services:
            problems.append(f"{path}: no service '{name}'")
            return
    coord, worker = services["coordinator"], services["worker"]
    if "container_name" in worker:
        problems.append(f"{path}: worker has container_name, so --scale cannot work")
    for name in ("coordinator", "worker"):
        if "healthcheck" not in services[name]:
            problems.append(f"{path}: {name} has no healthcheck")
    vols = doc.get("volumes") or {}
    if not any(str(v).split(":")[0] in vols for v in coord.get("volumes", [])):
        problems.append(f"{path}: the coordinator's database is not on a named volume")
    listen = env_dict(coord).get("GAITFORGE_LISTEN", "0.0.0.0:50051")
    target = env_dict(worker).get("GAITFORGE_COORDINATOR", "")
    if target != f"coordinator:{listen.rsplit(':', 1)[1]}":
        problems.append(f"{path}: worker dials '{target}' but the coordinator listens on {listen}")
    grace = seconds(worker.get("stop_grace_period", "10s"))
    if grace is None or grace < 120:
        problems.append(f"{path}: worker stop_grace_period < 120s")
    published = [str(p).rsplit(":", 1)[-1] for p in coord.get("ports", [])]
    metrics = env_dict(coord).get("GAITFORGE_METRICS_LISTEN")
    for addr in (listen, metrics):
        if addr and addr.rsplit(":", 1)[1] not in published:
            problems.append(f"{path}: container port of {addr} is not published")


def lint(repo):
    problems, count = [], 0
    for path in yaml_files(repo):
        rel = os.path.relpath(path, repo)
        try:
            docs = load_all(path)
        except yaml.YAMLError as e:
            problems.append(f"{rel}: not valid YAML: {e}")
            continue
        count += 1
        if not docs:
            problems.append(f"{rel}: empty")
        if f"{os.sep}k8s{os.sep}" in path and not path.endswith("-values.yaml"):
            check_k8s(rel, docs, problems, base=os.path.dirname(path))
        elif os.path.basename(path) == "compose.yaml":
            check_compose(rel, docs[0], problems)
    for p in problems:
        print(p)
    print(f"{count} YAML files parsed", file=sys.stderr)
    return 1 if problems else 0


def compose_service(repo, service):
    with open(os.path.join(repo, "deploy", "compose.yaml")) as f:
        return yaml.safe_load(f)["services"][service]


def compose_env(repo, service, envfile, overrides):
    env = dict(os.environ)
    with open(envfile) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                k, v = line.split("=", 1)
                env[k] = v
    svc = compose_service(repo, service)
    out = {k: interpolate(v, env) for k, v in env_dict(svc).items()}
    for o in overrides:
        k, v = o.split("=", 1)
        out[k] = v
    for k, v in out.items():
        print(f"export {k}={shlex.quote(v)}")
    words = svc.get("command") or []
    print("GF_COMMAND=(" + " ".join(shlex.quote(interpolate(w, env)) for w in words) + ")")
    return 0


def compose_health(repo, service):
    test = compose_service(repo, service)["healthcheck"]["test"]
    if test[0] not in ("CMD", "CMD-SHELL"):
        print("healthcheck must be CMD or CMD-SHELL", file=sys.stderr)
        return 1
    for w in test[1:]:
        print(w)
    return 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "lint":
        return lint(argv[2])
    if len(argv) >= 5 and argv[1] == "compose-env":
        return compose_env(argv[2], argv[3], argv[4], argv[5:])
    if len(argv) == 4 and argv[1] == "compose-health":
        return compose_health(argv[2], argv[3])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
