"""Shared helpers of the benchmark scripts: best-of-N timing, machine/load header, tables.

Timings are wall-clock (``time.perf_counter``). Every script repeats each measurement and
reports the best (minimum) time, which is the least disturbed by other work on the machine;
the load average is printed before and after each table so that a disturbed run shows.
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:  # numpy_reference lives next to the scripts
    sys.path.insert(0, str(HERE))


def best_of(fn, repeats: int, warmup: int = 0):
    """Calls ``fn()`` ``warmup + repeats`` times; returns (best seconds, last return value)."""
    value = None
    for _ in range(warmup):
        value = fn()
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        value = fn()
        best = min(best, time.perf_counter() - start)
    return best, value


def _busy_seconds() -> float:
    """CPU seconds spent busy by all cores since boot (from /proc/stat; 0 if unavailable)."""
    try:
        with open("/proc/stat") as f:
            fields = [int(v) for v in f.readline().split()[1:]]
    except (OSError, ValueError):
        return 0.0
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)
    return (sum(fields[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def _own_seconds() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


_mark = [time.perf_counter(), _busy_seconds(), _own_seconds()]


def other_work(reset: bool = False) -> str:
    """CPU used by *other* processes since the last reset (the header), in cores on average:
    machine busy time minus this process's (and its waited-for children's) CPU time."""
    now, busy, own = time.perf_counter(), _busy_seconds(), _own_seconds()
    wall = now - _mark[0]
    others = max(0.0, (busy - _mark[1]) - (own - _mark[2]))
    if reset:
        _mark[:] = [now, busy, own]
    if wall <= 0 or busy == 0.0:
        return "other work n/a"
    return (f"other processes used {others / wall:.2f} cores on average "
            f"during the {wall:.1f} s since the header")


def wait_quiet(limit: float, threshold: float = 0.1, sample: float = 3.0) -> float:
    """Waits (at most ``limit`` s) until other processes use less than ``threshold`` cores
    over ``sample`` s; returns the last sampled use (cores). Does nothing when limit <= 0."""
    use = float("nan")
    start = time.perf_counter()
    while limit > 0 and time.perf_counter() - start < limit:
        b0, o0 = _busy_seconds(), _own_seconds()
        time.sleep(sample)
        use = max(0.0, (_busy_seconds() - b0) - (_own_seconds() - o0)) / sample
        if use < threshold:
            break
    return use


def load() -> str:
    """The 1-minute load average (and the number of cores) as a short string."""
    try:
        one, five, _ = os.getloadavg()
        return f"load avg {one:.2f} (1 min) {five:.2f} (5 min) on {os.cpu_count()} cores"
    except OSError:
        return "load avg n/a"


def header(title: str) -> None:
    """Prints the title, the machine, the library build and the current load."""
    import numpy
    import scipy

    import mdrvisc
    from mdrvisc import _core

    so = Path(_core.__file__)
    digest = hashlib.sha1(so.read_bytes()).hexdigest()[:10]
    stamp = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(so.stat().st_mtime))
    print(f"== {title}")
    print(f"   python {platform.python_version()}, numpy {numpy.__version__}, "
          f"scipy {scipy.__version__}, mdrvisc {mdrvisc.__version__} "
          f"(_core sha1 {digest}, built {stamp})")
    quiet = float(os.environ.get("BENCH_WAIT_QUIET", "0") or 0)
    if quiet > 0:
        use = wait_quiet(quiet)
        print(f"   waited for a quiet machine (BENCH_WAIT_QUIET={quiet:g} s): other processes "
              f"at {use:.2f} cores when starting")
    threads = os.environ.get("RAYON_NUM_THREADS", "unset (all cores)")
    print(f"   {platform.machine()}, {os.cpu_count()} cores, RAYON_NUM_THREADS={threads}; "
          f"{load()}")
    other_work(reset=True)  # start the count of other processes' CPU time


def table(columns, rows, formats=None) -> None:
    """Prints ``rows`` (sequences) under ``columns`` with per-column format strings."""
    formats = formats or ["{}"] * len(columns)
    cells = [[fmt.format(v) if v is not None else "-" for fmt, v in zip(formats, row)]
             for row in rows]
    widths = [max(len(c), *(len(r[i]) for r in cells)) if cells else len(c)
              for i, c in enumerate(columns)]
    print("  ".join(c.rjust(w) for c, w in zip(columns, widths)))
    print("  ".join("-" * w for w in widths))
    for r in cells:
        print("  ".join(v.rjust(w) for v, w in zip(r, widths)))
    print(f"   ({load()}; {other_work()})")


def interleaved(funcs: dict, rounds: int, warmup: bool = True) -> dict:
    """Times several callables *interleaved*: each round calls every one of them once, in
    order, so that all see the same machine state (a shared VM's speed can drift by up to 2x
    over minutes). ``funcs`` maps a name to ``fn`` or to ``(fn, inner)``, where ``fn()`` is
    called ``inner`` times per sample and the sample is divided by ``inner`` (for calls too
    short to time alone; 0: chosen from the warm-up call for ~20 ms samples). Returns
    name -> (best seconds per call, last return value). With ``warmup``, every function is
    called once, untimed, first."""
    specs = {k: (v if isinstance(v, tuple) else (v, 1)) for k, v in funcs.items()}
    out = {k: [float("inf"), None] for k in specs}
    if warmup:
        for k, (fn, inner) in list(specs.items()):
            start = time.perf_counter()
            out[k][1] = fn()
            if inner == 0:  # auto: samples of about 20 ms
                specs[k] = (fn, inner_count(time.perf_counter() - start))
    for _ in range(rounds):
        for k, (fn, inner) in specs.items():
            start = time.perf_counter()
            for _ in range(inner):
                value = fn()
            out[k][0] = min(out[k][0], (time.perf_counter() - start) / inner)
            out[k][1] = value
    return {k: tuple(v) for k, v in out.items()}


def inner_count(seconds_per_call: float, target: float = 0.02) -> int:
    """Calls per sample so that a sample lasts about ``target`` seconds."""
    return max(1, int(target / max(seconds_per_call, 1e-7)))


def pressure_for_fraction(pressure_at, fraction: float, estimate: float,
                          tries: int = 8) -> tuple[float, list[str]]:
    """Mean pressure (Pa) at which ``pressure_at(pbar)`` (a contact's pressure field) has the
    contact fraction ``fraction`` to 1 %: secant steps on the fraction from ``estimate``.
    Returns it and a log line per step."""
    log, points = [], []
    pbar = estimate
    for _ in range(tries):
        p = pressure_at(pbar)
        got = float((p > 0).sum()) / p.size
        log.append(f"pbar {pbar:.6g} Pa -> {got:.4f}")
        points.append((pbar, got))
        if abs(got / fraction - 1.0) < 0.01:
            break
        if len(points) == 1:
            pbar *= fraction / got
        else:
            (p0, f0), (p1, f1) = points[-2:]
            pbar = p1 + (fraction - f1) * (p1 - p0) / (f1 - f0) if f1 != f0 else p1
    return pbar, log


def run_worker(cmd: list[str], timeout: float) -> dict:
    """Runs a peer's worker script ``cmd`` (its venv's python first) outside this venv (no
    PYTHONPATH, no VIRTUAL_ENV) and returns the JSON of its last output line, or
    ``{"failed": why}`` when it timed out or exited with an error."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return {"failed": f"timed out after {timeout:.0f} s"}
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-3:]
        return {"failed": f"rc {proc.returncode}: " + " | ".join(tail)}
    return json.loads(proc.stdout.strip().splitlines()[-1])
