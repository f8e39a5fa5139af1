#!/usr/bin/python3
"""Usability figures (issue 24): how fast a user sees a study, what the dashboard weighs,
and what the Python client costs.

1. Time to the first point: from starting `gaitforge local SPEC --workers 2` (the README's
   main job by default) to the first generation the dashboard's history endpoint serves
   (the page asks every second, so a browser shows it up to 1 s later).
2. Page weight: the dashboard's page and every asset it loads, as served (bytes) and as
   gzip would make them.
3. The Python client's overhead per `history` call on a 150-generation study: the client
   (dict rows; DataFrame when pandas is present) against the raw generated gRPC call, same
   channel, same coordinator.

    /usr/bin/python3 bench/usability.py [--bin build/bin] [--spec examples/caterpillar-ga.yaml]
        [--calls 50] [--out bench/results]

Prints a table and writes usability-DATE.json in --out.
"""
import argparse
import gzip
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(REPO, "clients", "python"))


def get(url):
    with urllib.request.urlopen(url, timeout=10) as r:
        return r.read()


def first_point(binary, spec, work):
    """Seconds from launching `local` to the dashboard serving generation 0."""
    start = time.monotonic()
    proc = subprocess.Popen([binary, "local", os.path.abspath(spec), "--workers", "2"], cwd=work,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    url = None
    for line in proc.stderr:
        m = re.match(r"dashboard: (http://[^#\s]+)#/study/(\S+)", line)
        if m:
            url, study = m.group(1), m.group(2)
            break
    if url is None:
        raise SystemExit("gaitforge local printed no dashboard address")
    seen_url = time.monotonic() - start
    while True:
        history = json.loads(get(f"{url}api/studies/{study}/history"))
        if history.get("generations"):
            break
        time.sleep(0.02)
    first = time.monotonic() - start
    proc.send_signal(signal.SIGINT)
    proc.wait(timeout=60)
    return url, seen_url, first


def page_weight(url):
    """(bytes as served, bytes gzipped, files) of the page and what it loads."""
    index = get(url)
    assets = re.findall(rb'(?:src|href)="([^"#:]+)"', index)
    files = {"/": index}
    for a in assets:
        path = a.decode().lstrip("./")
        files[path] = get(url + path)
    raw = sum(len(b) for b in files.values())
    packed = sum(len(gzip.compress(b, 9)) for b in files.values())
    return raw, packed, sorted(files)


def client_overhead(binaries, calls):
    from gaitforge_client import Client, stubs
    spec = {"name": "history-bench", "seed": 1, "population": 20, "generations": 150,
            "objective": {"name": "analytic.sphere"}}
    out = {}
    with tempfile.TemporaryDirectory() as d, \
            Client.local(db=os.path.join(d, "h.db"), workers=2, binaries=binaries) as gf:
        study = gf.submit(spec)
        gf.watch(study)
        pb = stubs.load("study_pb2")
        request = pb.GetHistoryRequest(study_id=study)

        def timed(fn):
            fn()  # warm
            t = time.perf_counter()
            for _ in range(calls):
                fn()
            return (time.perf_counter() - t) / calls * 1e3

        out["rows"] = len(gf.history(study))
        out["raw_grpc_ms"] = timed(lambda: gf._studies.GetHistory(request, timeout=30))
        out["client_ms"] = timed(lambda: gf.history(study))
        try:
            import pandas  # noqa: F401
            out["dataframe_ms"] = timed(lambda: gf.history(study, as_dataframe=True))
        except ImportError:
            out["dataframe_ms"] = None
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "bin"))
    ap.add_argument("--spec", default=os.path.join(REPO, "examples", "caterpillar-ga.yaml"))
    ap.add_argument("--calls", type=int, default=50)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    binary = os.path.join(a.bin, "gaitforge")
    with tempfile.TemporaryDirectory() as work:
        url, seen_url, first = first_point(binary, a.spec, work)
        # The page's weight, from a read-only dashboard of the interrupted study's database
        # (again while `local`'s coordinator, stopping, still names its own page).
        for attempt in range(20):
            dash = subprocess.Popen([binary, "dashboard"], cwd=work, text=True,
                                    stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
            page = dash.stdout.readline().strip()
            try:
                raw, packed, files = page_weight(page if page.endswith("/") else page + "/")
                break
            except OSError:
                time.sleep(0.5)
            finally:
                dash.send_signal(signal.SIGINT)
                dash.wait(timeout=30)
    py = client_overhead(a.bin, a.calls)
    result = {"spec": os.path.relpath(a.spec, REPO), "dashboard_url_s": seen_url,
              "first_point_s": first, "page_bytes": raw, "page_gzip_bytes": packed,
              "page_files": files, "python": py}
    print(f"{'measure':44s} value")
    print(f"{'local -> dashboard address printed':44s} {seen_url:.2f} s")
    print(f"{'local -> first generation on the dashboard API':44s} {first:.2f} s (+ up to 1 s page poll)")
    print(f"{'page weight, as served':44s} {raw / 1024:.1f} KiB in {len(files)} files")
    print(f"{'page weight, gzip -9 (not served compressed)':44s} {packed / 1024:.1f} KiB")
    print(f"{'history, raw gRPC call ({} rows)'.format(py['rows']):44s} {py['raw_grpc_ms']:.2f} ms/call")
    print(f"{'history, Python client (dict rows)':44s} {py['client_ms']:.2f} ms/call "
          f"(+{py['client_ms'] - py['raw_grpc_ms']:.2f})")
    if py["dataframe_ms"] is not None:
        print(f"{'history, Python client (DataFrame)':44s} {py['dataframe_ms']:.2f} ms/call")
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, time.strftime("usability-%Y-%m-%d.json"))
    with open(path, "w") as f:
        json.dump(result, f, indent=1)
    print("wrote", path)


if __name__ == "__main__":
    main()
