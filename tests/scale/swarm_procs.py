"""Runs gaitforge-swarm (bench/swarm: N emulated workers in one process) against a real
coordinator: one measured cell of bench/scaling.py, or the faults run of scale_test.py.
Process helpers and the read-only database helpers come from tests/chaos."""
import json
import os
import re
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "chaos"))
import chaos  # noqa: E402


def sized_spec(workers, studies, mean_s, seconds, seed=1, elite=10, jobs_per_worker=None,
               work_s=2.0):
    """A GA spec whose generations give every worker about `jobs_per_worker` jobs (by default
    ~`work_s` seconds of work per generation) and whose run lasts about `seconds`.

    Generation 0 evaluates the whole population, later ones all but the `elite`, so no
    population fills every generation with whole rounds of k jobs per worker. Population
    k*N + elite (later generations exact) costs generation 0 one extra round: N evaluation
    times of idle worker time once. Population k*N (generation 0 exact) leaves `elite`
    workers one evaluation short in each later generation: elite evaluation times per
    generation. The spec takes whichever idles the pool less over the run."""
    k = jobs_per_worker or max(1, round(work_s / mean_s))
    gens = max(3, round(seconds / (k * mean_s)))
    full = -(-k * workers // studies)
    first_exact = elite * studies * (gens - 1) < workers
    per_study = max(elite + 2, full if first_exact else full + elite)
    return {"name": "swarm", "seed": seed, "engine": "ga", "population": per_study,
            "generations": gens, "objective": {"name": "analytic.rastrigin"},
            "ga": {"elite": elite, "mutation_rate": 0.1}}


def metrics_text(port):
    with urllib.request.urlopen("http://127.0.0.1:%d/metrics" % port, timeout=10) as r:
        return r.read().decode()


def histogram_quantiles(text, name, qs=(0.5, 0.99)):
    """Quantiles of a Prometheus histogram (linear within buckets), in its unit."""
    buckets = []
    for m in re.finditer(r'^%s_bucket\{le="([^"]+)"\} (\S+)$' % name, text, re.M):
        le = float("inf") if m.group(1) == "+Inf" else float(m.group(1))
        buckets.append((le, float(m.group(2))))
    buckets.sort()
    if not buckets or buckets[-1][1] == 0:
        return [None for _ in qs]
    total, out = buckets[-1][1], []
    for q in qs:
        want, prev_le, prev_n = q * total, 0.0, 0.0
        for le, n in buckets:
            if n >= want:
                le = prev_le * 2 if le == float("inf") else le
                frac = (want - prev_n) / (n - prev_n) if n > prev_n else 1.0
                out.append(prev_le + frac * (le - prev_le))
                break
            prev_le, prev_n = le, n
    return out


def metric_sum(text, name):
    m = re.search(r"^%s (\S+)$" % name, text, re.M)
    return float(m.group(1)) if m else None


def start_coordinator(bin_dir, workdir, db, port=0, flags=(), new_session=True):
    coord = chaos.Coordinator(bin_dir, workdir, db, "127.0.0.1", port,
                              ["--metrics-listen", "127.0.0.1:0"] + list(flags),
                              new_session=new_session)
    coord.start()
    return coord


def metrics_port(coord):
    with open(coord.port_file) as f:
        lines = f.read().split()
    return int(lines[1]) if len(lines) > 1 else None


def run_swarm(bin_dir, workdir, coord, spec, workers, eval_dist, studies=1, extra=(),
              during=None, timeout=900):
    """Runs the swarm to the end of its studies; `during(proc)` is polled while it runs
    (the coordinator kill of the faults run). Returns the swarm's JSON figures."""
    spec_path = chaos.write_spec(spec, os.path.join(workdir, "spec.json"))
    argv = [os.path.join(bin_dir, "gaitforge-swarm"), "--coordinator", coord.target,
            "--spec", spec_path, "--workers", str(workers), "--eval", eval_dist,
            "--studies", str(studies), "--coordinator-pid", str(coord.proc.pid)] + list(extra)
    out_path = os.path.join(workdir, "swarm.json")
    with open(out_path, "w") as out, open(os.path.join(workdir, "swarm.log"), "w") as err:
        p = subprocess.Popen(argv, stdout=out, stderr=err, stdin=subprocess.DEVNULL)
        end = time.monotonic() + timeout
        while p.poll() is None and time.monotonic() < end:
            if during:
                during(p)
            time.sleep(0.1)
        if p.poll() is None:
            p.kill()
            raise RuntimeError("swarm did not finish within %d s (see %s)" % (timeout, workdir))
    with open(out_path) as f:
        text = f.read().strip()
    if not text:
        raise RuntimeError("swarm printed nothing (exit %s; see %s/swarm.log)" % (p.returncode, workdir))
    res = json.loads(text)
    res["exit_code"] = p.returncode
    return res


def cell(bin_dir, workdir, workers, eval_dist, mean_s, studies=1, seconds=45, flags=(),
         work_s=2.0):
    """One measured cell: a fresh coordinator and database, the swarm, the figures."""
    os.makedirs(workdir, exist_ok=True)
    db = os.path.join(workdir, "scale.db")
    # In the swarm's session: Linux's autogroup scheduler shares the CPU evenly between
    # sessions, which gives a coordinator in a session of its own one core's worth against
    # the swarm at every barrier (1,024 x 500 ms: 0.91 against 0.93), as if the thousand
    # emulated workers' machines were its own. On a machine of its own it has every core.
    coord = start_coordinator(bin_dir, workdir, db, flags=flags, new_session=False)
    try:
        spec = sized_spec(workers, studies, mean_s, seconds, work_s=work_s)
        res = run_swarm(bin_dir, workdir, coord, spec, workers, eval_dist, studies)
        text = metrics_text(metrics_port(coord))
        p50, p99 = histogram_quantiles(text, "gaitforge_sqlite_commit_seconds")
        res["commit_ms_p50"] = p50 * 1000 if p50 is not None else None
        res["commit_ms_p99"] = p99 * 1000 if p99 is not None else None
        res["commits"] = metric_sum(text, "gaitforge_sqlite_commit_seconds_count")
        res["population"], res["generations"] = spec["population"], spec["generations"]
    finally:
        coord.stop()
    return res
