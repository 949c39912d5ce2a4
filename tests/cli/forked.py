"""A real process without a new interpreter: ``Forked`` runs a function in a child forked
from the test process, set up as Python sets up a fresh process running a script.

A fresh ``python -c ...`` that imports rprpr and its dependencies costs ~0.25 CPU-s; a
child forked from a test process that has them imported costs a few hundredths. The child
is a process of its own (its pid, its session, its signal handlers, its exit status, death
by a signal included), which is what tests of signals, workers and exit statuses look at.
What a fresh interpreter sets up at start-up is set up again in the child:

* signals: none blocked, none handled by Python code but SIGINT (``KeyboardInterrupt``,
  or ignored when asked, as a job started with SIGINT ignored has it), SIGPIPE and
  SIGXFSZ ignored, every other one at its default;
* standard streams: new ``sys.stdin``/``stdout``/``stderr`` on descriptors 0, 1 and 2
  (UTF-8; output strict and block-buffered, error line-buffered with backslashreplace),
  standard input from /dev/null;
* exit: ``SystemExit`` gives the status as the interpreter does, the standard output is
  flushed (a failure there is status 120), the child's own ``atexit`` functions run (not
  the test process's), and the child ends with ``os._exit``: nothing of pytest's runs
  twice.

The test process's garbage is frozen in the child (``gc.freeze``): a collection there
never walks the objects it inherited. A test whose subject is interpreter start-up itself
(what is imported, what a job inherits) starts a real interpreter instead; where several
such tests ask what a fresh process does, ``probe`` runs them all in one new interpreter,
each in a child forked from it before it has imported anything of rprpr (``fresh_probe``
and ``run_fresh``: the suite's probes in one such interpreter). ``run_rprpr`` runs
``python -m rprpr`` in a ``Forked`` child; ``run_served`` runs a script (the Action's, a
hook's command line) whose ``rprpr`` commands each run in one.
"""

from __future__ import annotations

import ast
import atexit
import contextlib
import gc
import io
import itertools
import json
import os
import selectors
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import traceback
import warnings
from collections.abc import Callable
from pathlib import Path


class Forked:
    """``target()`` in a forked child, as a script run by ``python -c`` with standard
    output and error on pipes (``stdout``, ``stderr``: binary streams), in a session of
    its own when ``new_session``. ``returncode`` as ``subprocess.Popen`` has it (-N: died
    of signal N) once ``wait`` or ``communicate`` has reaped the child.

    ``out``, ``err``: descriptors (a pseudo-terminal's, say) to give the child as its
    standard output and error instead of pipes (the caller closes and reads them;
    ``stdout`` and ``stderr`` are then None); ``env``: the child's whole environment."""

    def __init__(
        self,
        target: Callable[[], object],
        *,
        cwd: str | Path,
        new_session: bool = True,
        sigint: object = signal.default_int_handler,
        out: int | None = None,
        err: int | None = None,
        env: dict[str, str] | None = None,
    ) -> None:
        out_r, out_w = os.pipe() if out is None else (None, out)
        err_r, err_w = os.pipe() if err is None else (None, err)
        sys.stdout.flush()
        sys.stderr.flush()
        with warnings.catch_warnings():
            # Python >= 3.12 warns of a fork in a process with threads (a test runner's):
            # the child runs rprpr alone, as rprpr's own forked workers do
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
        if pid == 0:  # pragma: no cover (the child)
            try:
                for fd in (out_r, err_r):
                    if fd is not None:
                        os.close(fd)
                if env is not None:
                    os.environ.clear()
                    os.environ.update(env)
                _child(target, out_w, err_w, cwd, new_session, sigint)
            finally:  # _child ends the child itself; this, if a step before it failed
                os._exit(1)
        for r, w in ((out_r, out_w), (err_r, err_w)):
            if r is not None:
                os.close(w)
        self.pid = pid
        self.returncode: int | None = None
        # closed by communicate
        self.stdout = None if out_r is None else open(out_r, "rb", buffering=0)  # noqa: SIM115
        self.stderr = None if err_r is None else open(err_r, "rb", buffering=0)  # noqa: SIM115

    def wait(self, timeout: float | None = None) -> int:
        """The exit status, waiting for it (``TimeoutError`` once a ``HangGuard`` of
        ``timeout`` s has killed the child: a hang guard, not a measure)."""
        with HangGuard(timeout, self._signal) as guard:
            if self.returncode is None:
                _, status = os.waitpid(self.pid, 0)
                self.returncode = os.waitstatus_to_exitcode(status)
        if guard.fired:
            raise TimeoutError(f"process {self.pid} still running: killed")
        return self.returncode

    def poll(self) -> int | None:
        """The exit status if the child has ended (reaped now), else None."""
        if self.returncode is None:
            pid, status = os.waitpid(self.pid, os.WNOHANG)
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
        return self.returncode

    def _signal(self) -> None:
        """SIGKILL to the child and its session (new_session: its workers too)."""
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.pid, signal.SIGKILL)
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.pid, signal.SIGKILL)

    def _kill(self) -> None:
        """``_signal``, and the child reaped."""
        self._signal()
        with contextlib.suppress(ChildProcessError):
            os.waitpid(self.pid, 0)
        self.returncode = -signal.SIGKILL

    def communicate(self, timeout: float | None = None) -> tuple[bytes, bytes]:
        """What is left of standard output and error, to their end, and the child reaped
        (``TimeoutError`` once a ``HangGuard`` of ``timeout`` s has killed it)."""
        streams = [s for s in (self.stdout, self.stderr) if s is not None]
        got: dict[object, list[bytes]] = {s: [] for s in streams}
        with HangGuard(timeout, self._signal) as guard, selectors.DefaultSelector() as sel:
            for stream in streams:
                if not stream.closed:
                    sel.register(stream, selectors.EVENT_READ)
            while sel.get_map() and not guard.fired:  # (a killed child's workers may
                for key, _ in sel.select(1.0):  # hold its pipes: the guard ends the wait)
                    chunk = os.read(key.fd, 65536)
                    if chunk:
                        got[key.fileobj].append(chunk)
                    else:
                        sel.unregister(key.fileobj)
            for stream in streams:
                stream.close()
            self.wait()
        if guard.fired:
            raise TimeoutError(f"process {self.pid} still writing: killed")
        return tuple(b"".join(got.get(s, [])) for s in (self.stdout, self.stderr))  # type: ignore[return-value]


class HangGuard:
    """A hang guard: ``kill()`` from a timer thread once ``timeout`` s have passed (None:
    never), unless the ``with`` block has ended first; ``fired`` says whether it did. The
    waiting code reads no clock: a killed process ends the wait, which then raises, as
    ``subprocess.run(timeout=...)`` does for a hung child (never a measure of speed)."""

    def __init__(self, timeout: float | None, kill: Callable[[], object]) -> None:
        self.fired = False
        self._timer: threading.Timer | None = None
        if timeout is not None:

            def fire() -> None:
                self.fired = True
                kill()

            self._timer = threading.Timer(timeout, fire)
            self._timer.daemon = True

    def __enter__(self) -> HangGuard:
        if self._timer is not None:
            self._timer.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._timer is not None:
            self._timer.cancel()


def rprpr_main(*args: str) -> None:
    """``python -m rprpr ARGS``, as the target of a ``Forked`` child: with rprpr's own
    workers (forked per check), whatever the test process audits its checks with
    (``tests/conftest.py``'s in-process worker, which the fork inherits)."""
    import runpy

    from rprpr.cli import workers

    workers.Workers = getattr(workers.Workers, "real", workers.Workers)  # type: ignore[misc]

    sys.argv = ["rprpr", *args]
    runpy.run_module("rprpr", run_name="__main__", alter_sys=True)


def run_rprpr(
    args: list[str], cwd: str | Path, timeout: float = 120
) -> subprocess.CompletedProcess[str]:
    """``python -m rprpr ARGS`` in ``cwd``, in a forked child (``Forked``): its exit status
    and its standard output and error (UTF-8), as ``subprocess.run(..., capture_output=True,
    text=True)`` gives them for a new interpreter."""
    proc = Forked(lambda: rprpr_main(*args), cwd=cwd)
    out, err = proc.communicate(timeout=timeout)
    assert proc.returncode is not None
    return subprocess.CompletedProcess(
        ["rprpr", *args], proc.returncode, *(b.decode().replace("\r\n", "\n") for b in (out, err))
    )


# -- a script's rprpr commands, each in a forked child ---------------------------------------
# The client: an ``rprpr`` executable (Python without site: ~0.01 CPU-s to start) that hands
# its arguments, working directory, environment and standard output and error (the
# descriptors themselves) to ``run_served``'s process over a Unix socket, and exits with the
# status of the rprpr that ran there (128 + N when it died of signal N, as a shell reports
# it). The rprpr reads no standard input (a ``Forked`` child's is /dev/null): the scripts
# served name their task files.
CLIENT = """
import json, os, socket, sys
request = json.dumps([sys.argv[1:], os.getcwd(), dict(os.environ)]).encode()
with socket.socket(socket.AF_UNIX) as s:
    s.connect(SERVER)
    socket.send_fds(s, [len(request).to_bytes(8, "big") + request], [1, 2])
    s.shutdown(socket.SHUT_WR)
    status = int(s.makefile("rb").read())
sys.exit(status if status >= 0 else 128 - status)
"""


def _request(conn: socket.socket) -> tuple[list[str], str, dict[str, str], list[int]]:
    """A client's request: (arguments, working directory, environment, its standard
    output and error); a client that stalls mid-request for 30 s is an error."""
    conn.settimeout(30)
    data, fds, _, _ = socket.recv_fds(conn, 65536, 2)
    while len(data) < 8 or len(data) < 8 + int.from_bytes(data[:8], "big"):
        chunk = conn.recv(65536)
        assert chunk, "the client hung up mid-request"
        data += chunk
    args, cwd, env = json.loads(data[8 : 8 + int.from_bytes(data[:8], "big")])
    return args, cwd, env, fds


def run_served(
    command: list[str], *, cwd: str | Path, env: dict[str, str], timeout: float = 120
) -> subprocess.CompletedProcess[str]:
    """``command`` (a script, a hook's command line) run as ``subprocess.run(...,
    capture_output=True, text=True)`` runs it, with an ``rprpr`` first on its PATH whose
    every run is ``python -m rprpr`` in a child forked from this process (``Forked``, with
    the client's arguments, working directory, environment and standard output and error)
    instead of a new interpreter. For the paths where rprpr's own start-up is not the
    subject: the script's or the hook's handling of its inputs, and what rprpr answers."""
    with tempfile.TemporaryDirectory(prefix="rprpr-") as tmp:  # short: a socket's path
        server_path, bin_dir = os.path.join(tmp, "s"), os.path.join(tmp, "bin")
        os.mkdir(bin_dir)
        client = os.path.join(bin_dir, "rprpr")
        with open(client, "w", encoding="utf-8") as f:
            f.write(f"#!{sys.executable} -S\nSERVER = {server_path!r}\n{CLIENT}")
        os.chmod(client, 0o755)
        env = {**env, "PATH": f"{bin_dir}{os.pathsep}{env.get('PATH', '')}"}
        with socket.socket(socket.AF_UNIX) as server:
            server.bind(server_path)
            server.listen()
            proc = subprocess.Popen(
                command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE
            )
            assert proc.stdout is not None and proc.stderr is not None
            got: dict[int, list[bytes]] = {proc.stdout.fileno(): [], proc.stderr.fileno(): []}
            serving: list[tuple[socket.socket, Forked]] = []

            def kill() -> None:  # the script and every rprpr it started
                proc.kill()
                for _, child in list(serving):
                    child._signal()

            try:
                with HangGuard(timeout, kill) as guard, selectors.DefaultSelector() as sel:
                    sel.register(server, selectors.EVENT_READ)
                    for fd in got:
                        sel.register(fd, selectors.EVENT_READ)
                    # until the script has ended, its streams are closed and every
                    # rprpr it started has answered
                    while len(sel.get_map()) > 1 or serving or proc.poll() is None:
                        if guard.fired:
                            raise TimeoutError(f"{command[0]} still running: killed")
                        waiting = serving or len(sel.get_map()) == 1  # on a child, an exit
                        for key, _ in sel.select(0.02 if waiting else 1.0):
                            if key.fileobj is server:
                                conn, _ = server.accept()
                                try:
                                    args, where, child_env, fds = _request(conn)
                                except BaseException:
                                    conn.close()
                                    raise
                                try:
                                    child = Forked(
                                        lambda args=args: rprpr_main(*args),  # type: ignore[misc]
                                        cwd=where, out=fds[0], err=fds[1], env=child_env,
                                    )  # fmt: skip
                                finally:
                                    for fd in fds:
                                        os.close(fd)
                                serving.append((conn, child))
                            elif chunk := os.read(key.fd, 65536):
                                got[key.fd].append(chunk)
                            else:
                                sel.unregister(key.fd)
                        for conn, child in list(serving):
                            status = child.poll()
                            if status is not None:
                                conn.sendall(str(status).encode())
                                conn.close()
                                serving.remove((conn, child))
                returncode = proc.wait()  # it has ended (the loop's condition)
            finally:
                for conn, child in serving:
                    child._kill()
                    conn.close()
                if proc.poll() is None:
                    proc.kill()
                    proc.wait()
                proc.stdout.close()
                proc.stderr.close()
        out, err = (b"".join(got[fd]).decode() for fd in got)
        return subprocess.CompletedProcess(command, returncode, out, err)


def _child(
    target: Callable[[], object],
    out: int,
    err: int,
    cwd: str | Path,
    new_session: bool,
    sigint: object,
) -> None:  # pragma: no cover (runs in the child)
    code = 1
    try:
        gc.freeze()
        atexit._clear()  # the test process's exit functions are not the child's
        if new_session:
            os.setsid()
        _fresh_signals(sigint)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        os.dup2(out, 1)
        os.dup2(err, 2)
        for fd in {null, out, err}:
            os.close(fd)
        os.closerange(3, os.sysconf("SC_OPEN_MAX"))  # the test runner's pipes and files
        _fresh_warnings()
        gc.set_threshold(700, 10, 10)  # Python's own (tests/conftest.py raises them)
        os.chdir(cwd)
        streams = {
            "stdin": io.TextIOWrapper(
                io.BufferedReader(io.FileIO(0, "r", closefd=False)), encoding="utf-8"
            ),
            "stdout": io.TextIOWrapper(  # line by line on a terminal, as Python starts
                io.BufferedWriter(io.FileIO(1, "w", closefd=False)),
                encoding="utf-8",
                line_buffering=os.isatty(1),
            ),
            "stderr": io.TextIOWrapper(
                io.BufferedWriter(io.FileIO(2, "w", closefd=False)),
                encoding="utf-8",
                errors="backslashreplace",
                line_buffering=True,
            ),
        }
        for name, stream in streams.items():
            setattr(sys, name, stream)
            setattr(sys, f"__{name}__", stream)
        try:
            target()
            code = 0
        except SystemExit as e:
            if e.code is None:
                code = 0
            elif isinstance(e.code, int):
                code = e.code
            else:
                print(e.code, file=sys.stderr)
                code = 1
        except BaseException:
            traceback.print_exc()
            code = 1
        atexit._run_exitfuncs()
        try:
            sys.stdout.flush()
        except OSError as exc:
            code = 120
            os.write(2, f"Exception ignored on flushing sys.stdout: {exc!r}\n".encode())
        with contextlib.suppress(OSError):
            sys.stderr.flush()
    finally:
        os._exit(code)


def _fresh_warnings() -> None:  # pragma: no cover (runs in the child)
    """The warning filters a fresh interpreter starts with (not the test run's "error")."""
    warnings.resetwarnings()
    for category in (ResourceWarning, ImportWarning, PendingDeprecationWarning):
        warnings.simplefilter("ignore", category)
    warnings.simplefilter("ignore", DeprecationWarning)
    warnings.filterwarnings("default", category=DeprecationWarning, module="__main__")


def _fresh_signals(sigint: object) -> None:  # pragma: no cover (runs in the child)
    """The signal handlers and mask a fresh interpreter starts with."""
    signal.pthread_sigmask(signal.SIG_SETMASK, set())
    with contextlib.suppress(ValueError):
        signal.set_wakeup_fd(-1)
    for signum in signal.valid_signals():
        if signum in (signal.SIGKILL, signal.SIGSTOP):
            continue
        try:
            signal.signal(signum, signal.SIG_DFL)
        except (OSError, ValueError):
            continue
    signal.signal(signal.SIGINT, sigint)  # type: ignore[arg-type]
    signal.signal(signal.SIGPIPE, signal.SIG_IGN)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)


# -- fresh interpreters: many probes, one start-up ------------------------------------------
PROBER = """
import os, sys

def run(code):
    out_r, out_w = os.pipe()
    err_r, err_w = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.dup2(out_w, 1)
        os.dup2(err_w, 2)
        status = 0
        try:
            exec(compile(code, "<string>", "exec"), {"__name__": "__main__"})
        except SystemExit as e:
            if e.code is None or isinstance(e.code, int):
                status = e.code or 0
            else:
                print(e.code, file=sys.stderr)
                status = 1
        except BaseException:
            import traceback
            traceback.print_exc()
            status = 1
        import atexit
        atexit._run_exitfuncs()
        try:
            sys.stdout.flush()
        except OSError:
            status = 120
        sys.stderr.flush()
        os._exit(status)
    os.close(out_w)
    os.close(err_w)
    import selectors
    got = {out_r: [], err_r: []}
    with selectors.DefaultSelector() as sel:  # both pipes at once: neither fills up
        for fd in got:
            sel.register(fd, selectors.EVENT_READ)
        while sel.get_map():
            for key, _ in sel.select():
                chunk = os.read(key.fd, 65536)
                if chunk:
                    got[key.fd].append(chunk)
                else:
                    sel.unregister(key.fd)
                    os.close(key.fd)
    _, status = os.waitpid(pid, 0)
    return (os.waitstatus_to_exitcode(status),
            *(b"".join(got[fd]).decode() for fd in (out_r, err_r)))

results = {}
for name, floor, code in zip(sys.argv[1::3], sys.argv[2::3], sys.argv[3::3]):
    if floor:
        exec("import " + floor)
    results[name] = run(code)
sys.stdout.write(repr(results))
"""


def probe(probes: list[tuple[str, str, str]], cwd: str | Path) -> dict[str, tuple[int, str, str]]:
    """Each probe (name, floor, code) as ``python -c CODE`` would run it in ``cwd``: (exit
    status, standard output, standard error) by name.

    One interpreter (``PROBER``) runs them in order, each in a child forked from it; it
    imports nothing itself (os and sys are there from start-up) but, before each probe,
    the modules its floor names ("numpy, flint": those the probe would import first and
    takes as given), so that their start-up is paid once for all the probes after it.
    A probe ends as a script does: ``SystemExit`` gives its status, the exit functions it
    registered run, then standard output is flushed (status 120 if that fails); one that
    ends its process itself (``os._exit``) skips all that, as it would alone. Unlike
    ``python -c``, its ``sys.argv`` and ``__main__`` are the prober's, the few modules the
    prober uses (selectors, math) are imported already, and the interpreter's shutdown does
    not run: a probe asks what rprpr imports and how its program ends, not these."""
    # a floor's modules stay imported for the probes after it: a probe that asks what a
    # fresh process imports would find them there, so the floors only grow, in order
    floors = [{m.strip() for m in floor.split(",") if m.strip()} for _, floor, _ in probes]
    assert all(a <= b for a, b in itertools.pairwise(floors)), "probes: smaller floors first"
    argv = [x for p in probes for x in p]
    # numpy with one OpenBLAS thread, as rprpr's program (``cli.main.run``) starts it
    env = {"OPENBLAS_NUM_THREADS": "1", **os.environ}
    done = subprocess.run(
        [sys.executable, "-c", PROBER, *argv],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=cwd,
        env=env,
    )
    assert done.returncode == 0, done.stderr
    results: dict[str, tuple[int, str, str]] = ast.literal_eval(done.stdout)
    return results


# -- the suite's start-up probes: one interpreter for all of them ---------------------------
# Test modules register the probes they read (``fresh_probe``, at import); the session
# fixture ``fresh`` (tests/conftest.py) runs every registered probe in one ``probe`` call,
# and the tests that read it run in one test process (the xdist group "fresh"), so the
# interpreter and its floors start once for the suite, not once per test or module.
FRESH: dict[str, tuple[str, str | Callable[[Path], str], Path | None]] = {}


def fresh_probe(
    name: str, floor: str, code: str | Callable[[Path], str], cwd: Path | None = None
) -> None:
    """Register a probe for ``fresh``: ``code`` (or ``code(folder)``, which may write files
    into ``folder``, a new empty folder of its own, and gives the code) run as ``python -c``
    in ``cwd`` (None: in that folder), after the modules its ``floor`` names (see ``probe``)."""
    assert name not in FRESH, f"probe {name!r} registered twice"
    FRESH[name] = (floor, code, cwd)


def _modules(floor: str) -> frozenset[str]:
    return frozenset(m.strip() for m in floor.split(",") if m.strip())


def run_fresh(folder: Path) -> dict[str, tuple[int, str, str]]:
    """Every registered probe's (exit status, standard output, standard error), by name: in
    one interpreter, smaller floors first (each floor must hold the smaller ones)."""
    probes = []
    for i, (name, (floor, code, cwd)) in enumerate(FRESH.items()):
        own = folder / f"probe-{i}"
        own.mkdir()
        text = code(own) if callable(code) else code
        # os is there from start-up: changing directory imports nothing
        probes.append((name, floor, f"__import__('os').chdir({str(cwd or own)!r})\n{text}"))
    probes.sort(key=lambda p: len(_modules(p[1])))
    return probe(probes, folder)
