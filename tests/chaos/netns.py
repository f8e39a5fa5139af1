#!/usr/bin/python3
"""Multi-host chaos test for gaitforge (issue 5): real network namespaces on one box.

Topology (all names start with gfchaos-, all addresses in 10.231.7.0/24, no default
route anywhere, so nothing can reach any other address):

    gfchaos-hub    bridge br0 (10.231.7.2), one veth peer per host: vcoord, vw1, vw2, vw3
    gfchaos-coord  eth0 10.231.7.1   gaitforge-coordinator --listen 10.231.7.1:50051
    gfchaos-wN     eth0 10.231.7.1N  gaitforge-worker (N = 1..3)

Bad network on the worker links: `tc qdisc ... netem delay 20ms loss 1%` on both ends of
each worker link when the kernel has sch_netem. Without it (e.g. this CI kernel) the same
is emulated: 1% loss each way with nftables (`numgen random mod 100 < 1 drop`) in each worker
namespace, and 20 ms each way by a small TCP relay in gfchaos-hub that the workers dial
(10.231.7.2:50051 -> 10.231.7.1:50051). The summary says which was used.

Faults: a worker partitioned (its link set down on the hub side: packets silently dropped
both ways) for 2.5x its lease, then healed; a worker partitioned across a coordinator
kill -9 + restart (healed 1.5 leases after the restart); more coordinator kills mid-
generation; a worker kill -9 + replacement. Then the checker of chaos.py runs against a
fault-free reference (run on loopback with the same spec and seed).

Needs root and `ip netns`; otherwise prints why and exits 77 (skip). Namespaces are removed
on every exit path (try/finally + atexit), and leftovers of a killed run are removed first.
"""

import asyncio
import atexit
import os
import random
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chaos  # noqa: E402

PREFIX = "gfchaos-"
HUB = PREFIX + "hub"
COORD_NS = PREFIX + "coord"
SUBNET = "10.231.7."
COORD_IP = SUBNET + "1"
HUB_IP = SUBNET + "2"
PORT = 50051
SKIP = 77


def sh(*argv, check=True):
    r = subprocess.run(list(argv), capture_output=True, text=True)
    if check and r.returncode != 0:
        raise RuntimeError("%s: exit %d: %s" % (" ".join(argv), r.returncode, r.stderr.strip()))
    return r


def nsx(ns):
    return ["ip", "netns", "exec", ns]


def list_ours():
    r = sh("ip", "netns", "list", check=False)
    return [line.split()[0] for line in r.stdout.splitlines() if line.startswith(PREFIX)]


def teardown():
    """Ends this harness's processes, then removes every gfchaos- namespace (and so its links)."""
    chaos._cleanup_procs()
    for ns in list_ours():
        # Leftovers of an earlier run that was itself SIGKILLed: its processes in our namespaces.
        for pid in sh("ip", "netns", "pids", ns, check=False).stdout.split():
            try:
                os.kill(int(pid), 9)
            except (ProcessLookupError, ValueError):
                pass
        sh("ip", "netns", "del", ns, check=False)


def skip_reason():
    if os.geteuid() != 0:
        return "not root (network namespaces need CAP_NET_ADMIN)"
    if not shutil.which("ip"):
        return "`ip` (iproute2) is not installed"
    probe = PREFIX + "probe"
    sh("ip", "netns", "del", probe, check=False)
    r = sh("ip", "netns", "add", probe, check=False)
    if r.returncode != 0:
        return "`ip netns add` fails: " + r.stderr.strip()
    r = sh("ip", "-n", probe, "link", "add", "gfa", "type", "veth", "peer", "name", "gfb", check=False)
    sh("ip", "netns", "del", probe, check=False)
    if r.returncode != 0:
        return "cannot create veth pairs: " + r.stderr.strip()
    return None


def netem_available():
    probe = PREFIX + "probe"
    sh("ip", "netns", "add", probe, check=False)
    try:
        r = sh("ip", "netns", "exec", probe, "tc", "qdisc", "add", "dev", "lo", "root", "netem", "delay",
               "1ms", check=False)
        return r.returncode == 0, r.stderr.strip()
    finally:
        sh("ip", "netns", "del", probe, check=False)


def nft_available():
    return shutil.which("nft") is not None


class Net:
    """Builds the namespaces; partition()/heal() a worker host; impair() its link."""

    def __init__(self, n_workers, delay_ms=20, loss_pct=1):
        self.workers = ["%sw%d" % (PREFIX, i + 1) for i in range(n_workers)]
        self.delay_ms, self.loss_pct = delay_ms, loss_pct
        self.netem, netem_err = netem_available()
        self.nft = nft_available()
        self.mode = None
        self.netem_err = netem_err

    def peer(self, ns):
        return "v" + ns[len(PREFIX):]  # vcoord, vw1, ...

    def build(self):
        teardown()
        sh("ip", "netns", "add", HUB)
        sh("ip", "-n", HUB, "link", "set", "lo", "up")
        sh("ip", "-n", HUB, "link", "add", "br0", "type", "bridge")
        sh("ip", "-n", HUB, "addr", "add", HUB_IP + "/24", "dev", "br0")
        sh("ip", "-n", HUB, "link", "set", "br0", "up")
        hosts = [(COORD_NS, COORD_IP)] + [(ns, SUBNET + str(11 + i)) for i, ns in enumerate(self.workers)]
        for ns, ip in hosts:
            sh("ip", "netns", "add", ns)
            sh("ip", "-n", ns, "link", "set", "lo", "up")
            # Create the pair inside the hub, then move one end into the host: nothing is
            # ever created in the namespace this harness runs in.
            sh("ip", "-n", HUB, "link", "add", self.peer(ns), "type", "veth", "peer", "name", "eth0")
            sh("ip", "-n", HUB, "link", "set", "eth0", "netns", ns)
            sh("ip", "-n", HUB, "link", "set", self.peer(ns), "master", "br0")
            sh("ip", "-n", HUB, "link", "set", self.peer(ns), "up")
            sh("ip", "-n", ns, "addr", "add", ip + "/24", "dev", "eth0")
            sh("ip", "-n", ns, "link", "set", "eth0", "up")
        for ns in self.workers:
            self.impair(ns)
        ping = sh(*nsx(self.workers[0]), "/usr/bin/python3", "-c",
                  "import socket; s=socket.socket(); s.settimeout(3); r=s.connect_ex(('%s', 9)); "
                  "print(r)" % COORD_IP, check=False)
        # 111 = ECONNREFUSED: the coordinator host answered (nothing listens on port 9 yet).
        if ping.stdout.strip() != "111":
            raise RuntimeError("worker namespace cannot reach %s: %r %r" % (COORD_IP, ping.stdout, ping.stderr))

    def impair(self, ns):
        """delay/loss on the worker link, both directions."""
        if self.netem:
            self.mode = "tc netem delay %dms loss %d%% on both ends of each worker link" % (
                self.delay_ms, self.loss_pct)
            for args in (nsx(ns) + ["tc", "qdisc", "add", "dev", "eth0"],
                         ["ip", "netns", "exec", HUB, "tc", "qdisc", "add", "dev", self.peer(ns)]):
                sh(*args, "root", "netem", "delay", "%dms" % self.delay_ms, "loss", "%d%%" % self.loss_pct)
            return
        parts = []
        if self.nft and self.loss_pct > 0:
            rules = ("table inet gfchaos {\n"
                     " chain out { type filter hook output priority 0; policy accept;\n"
                     "  oifname \"eth0\" numgen random mod 100 < %d counter drop; }\n"
                     " chain in { type filter hook input priority 0; policy accept;\n"
                     "  iifname \"eth0\" numgen random mod 100 < %d counter drop; }\n}\n" % (
                         self.loss_pct, self.loss_pct))
            r = subprocess.run(nsx(ns) + ["nft", "-f", "-"], input=rules, text=True, capture_output=True)
            if r.returncode != 0:
                raise RuntimeError("nft: " + r.stderr)
            parts.append("%d%% packet loss each way (nftables numgen, in each worker namespace)" % self.loss_pct)
        else:
            parts.append("no packet loss (neither sch_netem nor nft is available)")
        if self.delay_ms > 0:
            parts.append("%d ms each way by a TCP relay in %s that the workers dial" % (self.delay_ms, HUB))
        self.mode = "sch_netem missing (%s); emulated: %s" % (self.netem_err or "?", "; ".join(parts))

    @property
    def use_relay(self):
        return not self.netem and self.delay_ms > 0

    def partition(self, ns):
        sh("ip", "-n", HUB, "link", "set", self.peer(ns), "down")

    def heal(self, ns):
        sh("ip", "-n", HUB, "link", "set", self.peer(ns), "up")

    def drop_counts(self):
        if self.netem or not self.nft:
            return None
        total = 0
        for ns in self.workers:
            out = sh(*nsx(ns), "nft", "list", "table", "inet", "gfchaos", check=False).stdout
            for tok in out.split("counter packets ")[1:]:
                total += int(tok.split()[0])
        return total


# --------------------------------------------------------------------------------------
# The delay relay (only without sch_netem): python3 netns.py --relay LISTEN_HOST PORT
# TARGET_HOST TARGET_PORT DELAY_MS, run inside gfchaos-hub.


async def _pump(reader, writer, delay):
    q = asyncio.Queue()

    async def sender():
        while True:
            due, data = await q.get()
            wait = due - time.monotonic()
            if wait > 0:
                await asyncio.sleep(wait)
            if data is None:
                try:
                    writer.write_eof()
                except OSError:
                    pass
                return
            writer.write(data)
            await writer.drain()

    task = asyncio.ensure_future(sender())
    try:
        while True:
            data = await reader.read(65536)
            q.put_nowait((time.monotonic() + delay, data or None))
            if not data:
                break
        await task
    except (OSError, asyncio.CancelledError):
        task.cancel()
        raise


async def _relay_conn(cr, cw, host, port, delay):
    try:
        ur, uw = await asyncio.open_connection(host, port)
    except OSError:
        cw.close()
        return
    a = asyncio.ensure_future(_pump(cr, uw, delay))
    b = asyncio.ensure_future(_pump(ur, cw, delay))
    done, pending = await asyncio.wait({a, b}, return_when=asyncio.FIRST_EXCEPTION)
    if any(t.exception() for t in done if not t.cancelled()):
        for t in pending:
            t.cancel()
    else:
        await asyncio.wait(pending)
    for w in (cw, uw):
        try:
            w.close()
        except OSError:
            pass


def relay_main(listen_host, listen_port, host, port, delay_ms):
    async def run():
        server = await asyncio.start_server(
            lambda r, w: _relay_conn(r, w, host, int(port), int(delay_ms) / 1000.0),
            listen_host, int(listen_port), reuse_address=True)
        print("relay %s:%s -> %s:%s, %s ms each way" % (listen_host, listen_port, host, port, delay_ms),
              flush=True)
        async with server:
            await server.serve_forever()

    asyncio.run(run())


# --------------------------------------------------------------------------------------


class NetCluster(chaos.LocalCluster):
    """Coordinator in gfchaos-coord; workers spread over the worker namespaces."""

    def __init__(self, bin_dir, workdir, spec, db, net, coord_flags):
        self.bin_dir, self.workdir, self.spec, self.db, self.threads = bin_dir, workdir, spec, db, 1
        self.net = net
        self.coord = chaos.Coordinator(bin_dir, workdir, db, COORD_IP, PORT, coord_flags, nsx(COORD_NS))
        self.workers = []  # [worker_id, Popen, namespace]
        self.n = 0
        self.study_id = None
        self.worker_target = ("%s:%d" % (HUB_IP, PORT)) if net.use_relay else self.coord.target

    def add_worker(self, like=None):
        ns = like[2] if like else self.net.workers[self.n % len(self.net.workers)]
        wid = "w%d-%s" % (self.n, ns[len(PREFIX):])
        self.n += 1
        w = [wid, chaos.start_worker(self.bin_dir, self.workdir, self.worker_target, wid, 1, nsx(ns)), ns]
        self.workers.append(w)
        return w


class NetNemesis(chaos.Nemesis):
    """The plan reaches COVERAGE in its six actions, the plain partition last: while it lasts
    (2.5 leases) no coordinator is killed, and with it first a 21.8 s CI run ended two
    actions short. Its actions are paced to the fault-free run, as chaos.py's are."""

    PLAN = ["partition_restart", "kill_coordinator", "kill_worker", "partition_restart", "kill_coordinator",
            "isolate_worker"]
    WEIGHTS = {"kill_worker": 2, "kill_coordinator": 1, "isolate_worker": 2, "partition_restart": 1}
    ISOLATE = "worker_partitions_past_lease"
    ISOLATE_VERB = ("partition", "heal")

    def isolated(self):
        # A partition cuts a whole host: every worker of that namespace.
        return {w[0] for w in self.c.workers if w[2] in {x[1][2] for x in self.pending}}

    def isolate(self, w):
        self.c.net.partition(w[2])

    def heal(self, w):
        self.c.net.heal(w[2])


def coordinator_has_flag(bin_dir, flag):
    r = subprocess.run([os.path.join(bin_dir, "gaitforge-coordinator"), "--help"], capture_output=True, text=True)
    return (flag + " ") in (r.stdout + r.stderr)


COVERAGE = {"coordinator_kills": 3, "coordinator_kills_mid_generation": 2, "worker_kills": 1,
            "worker_partitions_past_lease": 1, "partitions_across_restart": 2}


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--relay":
        relay_main(*sys.argv[2:7])
        return 0
    ap = chaos.common_args(__doc__, lease_ms=2000, workers=3)
    ap.add_argument("--delay-ms", type=int, default=20)
    ap.add_argument("--loss-pct", type=int, default=1)
    args = ap.parse_args(argv)
    reason = skip_reason()
    if reason:
        print("chaos(netns): SKIP: %s" % reason, flush=True)
        return SKIP
    bin_dir = os.path.abspath(args.bin_dir)
    err = chaos.check_bins(bin_dir)
    if err:
        print("chaos(netns): " + err, file=sys.stderr)
        return 1
    atexit.register(teardown)  # runs before chaos's own atexit handler (LIFO) and ends procs first
    workdir, spec, spec_path, res = chaos.new_run(args, "netns")
    try:
        ref_db, ref_id, res["reference_seconds"] = chaos.run_reference(
            bin_dir, os.path.join(workdir, "reference"), spec_path, args.workers)
        print("chaos(netns): reference run (loopback, no faults) completed in %.1f s" % res["reference_seconds"],
              flush=True)
        net = Net(args.workers, args.delay_ms, args.loss_pct)
        try:
            net.build()
            cdir = os.path.join(workdir, "chaos")
            os.makedirs(cdir)
            flags = ["--lease-ms", str(args.lease_ms), "--max-attempts", str(args.max_attempts)]
            if coordinator_has_flag(bin_dir, "--insecure"):
                flags.append("--insecure")  # plaintext on a non-loopback listener: a private test net
            cl = NetCluster(bin_dir, cdir, spec, os.path.join(cdir, "chaos.db"), net, flags)
            res["network"] = "%d worker hosts + 1 coordinator host on bridge %s/24; %s" % (
                args.workers, SUBNET + "0", net.mode)
            if net.use_relay:
                chaos.spawn(["/usr/bin/python3", os.path.abspath(__file__), "--relay", HUB_IP, str(PORT),
                             COORD_IP, str(PORT), str(args.delay_ms)], os.path.join(cdir, "relay.log"), nsx(HUB))
            cl.coord.start()
            for _ in range(args.workers):
                cl.add_worker()
            nem = NetNemesis(cl, random.Random(res["nemesis_seed"]), args.lease_ms, interval=(1.5, 2.5),
                             first_interval=chaos.paced_interval(res["reference_seconds"]))
            chaos.chaos_phase(cl, nem, spec_path, args, res, ref_db, ref_id, COVERAGE, prefix=nsx(COORD_NS))
            drops = net.drop_counts()
            if drops is not None:
                res["network"] += "; %d packets dropped by the loss rules" % drops
        finally:
            teardown()
            left = list_ours()
            if left:
                res.setdefault("error", "namespaces left behind: %s" % left)
                res["pass"] = False
    except Exception as e:
        import traceback
        res["error"] = "%s: %s" % (type(e).__name__, e)
        traceback.print_exc()
    return chaos.finish_run(args, res)


if __name__ == "__main__":
    sys.exit(main())
