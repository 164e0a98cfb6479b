#!/usr/bin/env bash
# Runs every mdrvisc benchmark and prints its tables (see benchmarks/README.md).
# Usage: benchmarks/run_all.sh [--quick]   (--quick: fewer repeats, for a smoke run)
# Needs the package installed (pip install . or maturin develop --release) in the active env.
# BENCH_WAIT_QUIET=SECONDS: each script first waits (up to that long) until other processes
# use < 0.1 cores; bench_threads.py also waits before each subprocess (--wait-quiet, 60 s).
# bench_peers.py is not run here: it needs the peer codes' own venv (benchmarks/README.md).
set -euo pipefail
cd "$(dirname "$0")"
PY=${PYTHON:-python}
QUICK=()
if [[ "${1:-}" == "--quick" ]]; then QUICK=(--quick); fi

echo "### bench_mdr.py"
if [[ ${#QUICK[@]} -gt 0 ]]; then "$PY" bench_mdr.py --repeats 5; else "$PY" bench_mdr.py; fi
echo
echo "### bench_operator.py"
"$PY" bench_operator.py "${QUICK[@]}"
echo
echo "### bench_bem.py"
"$PY" bench_bem.py "${QUICK[@]}"
echo
echo "### bench_dense_crossover.py"
if [[ ${#QUICK[@]} -gt 0 ]]; then "$PY" bench_dense_crossover.py --repeats 2; else "$PY" bench_dense_crossover.py; fi
echo
echo "### bench_active_set.py"
if [[ ${#QUICK[@]} -gt 0 ]]; then "$PY" bench_active_set.py --grids 128 256 --repeats 2; else "$PY" bench_active_set.py; fi
echo
echo "### bench_threads.py"
if [[ ${#QUICK[@]} -gt 0 ]]; then "$PY" bench_threads.py --quick --rounds 1; else "$PY" bench_threads.py --rounds 3; fi
echo
echo "### bench_sweep.py"
if [[ ${#QUICK[@]} -gt 0 ]]; then "$PY" bench_sweep.py --scenes 40; else "$PY" bench_sweep.py; fi
