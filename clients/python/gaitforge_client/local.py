"""A private coordinator and workers on loopback, as `gaitforge local` starts them.

The coordinator listens on 127.0.0.1 with a port it picks (--port-file); workers connect
to it. Logs go to logs/ in the database's folder. Everything is stopped (SIGTERM, then
SIGKILL after `grace` s) when the cluster closes.
"""
import os
import subprocess
import tempfile
import time

from .errors import InvalidRequest, Unavailable
from .stubs import SOURCE_TREE

_TOKEN_VARS = ("GAITFORGE_CLIENT_TOKEN", "GAITFORGE_WORKER_TOKEN", "GAITFORGE_ADMIN_TOKEN")


def bin_dir():
    """$GAITFORGE_BIN_DIR, else build/bin of the source tree."""
    return os.environ.get("GAITFORGE_BIN_DIR") or os.path.join(SOURCE_TREE, "build", "bin")


class LocalCluster:
    def __init__(self, db, workers=1, threads=1, binaries=None, start_timeout=30.0):
        folder = os.path.dirname(os.path.abspath(db))
        if not os.path.isdir(folder):
            raise InvalidRequest(f"db {db}: folder {folder} does not exist; create it first")
        self.db = os.path.abspath(db)
        self.logs = os.path.join(folder, "logs")
        self._bin = binaries or bin_dir()
        self._procs = []
        self._tmp = tempfile.TemporaryDirectory(prefix="gaitforge-py-")
        self._env = {k: v for k, v in os.environ.items() if k not in _TOKEN_VARS}
        os.makedirs(self.logs, exist_ok=True)
        try:
            self.target = f"127.0.0.1:{self._start_coordinator(start_timeout)}"
            for i in range(workers):
                self._spawn([self._binary("gaitforge-worker"), "--coordinator", self.target,
                             "--threads", str(threads), "--worker-id", f"py-{i}"], f"worker-{i}.log")
        except BaseException:
            self.close()
            raise

    def _binary(self, name):
        path = os.path.join(self._bin, name)
        if not os.access(path, os.X_OK):
            raise Unavailable(f"{path} not found: build gaitforge or set GAITFORGE_BIN_DIR")
        return path

    def _spawn(self, argv, log_name):
        with open(os.path.join(self.logs, log_name), "ab") as log:
            proc = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, env=self._env)
        self._procs.append(proc)
        return proc

    def _start_coordinator(self, timeout):
        port_file = os.path.join(self._tmp.name, "port")
        proc = self._spawn([self._binary("gaitforge-coordinator"), "--listen", "127.0.0.1:0",
                            "--db", self.db, "--port-file", port_file], "coordinator.log")
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if proc.poll() is not None:
                raise Unavailable(f"the local coordinator exited with {proc.returncode}; "
                                  f"see {os.path.join(self.logs, 'coordinator.log')}")
            if os.path.exists(port_file):
                with open(port_file) as f:
                    return int(f.readline())
            time.sleep(0.05)
        raise Unavailable(f"the local coordinator did not start within {timeout} s")

    def close(self, grace=5.0):
        """Stops the workers, then the coordinator (which flushes its writes)."""
        for proc in self._procs[1:] + self._procs[:1]:
            if proc.poll() is None:
                proc.terminate()
            try:
                proc.wait(grace)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        self._procs = []
        self._tmp.cleanup()
