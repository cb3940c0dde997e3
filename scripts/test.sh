#!/usr/bin/env bash
# The tests, on a fresh machine with a Rust toolchain and Python 3: cargo's tests, then
# the Python module's. It makes its own virtual environment (target/python/venv),
# installs python/requirements-test.txt into it from PyPI (maturin, NumPy, pandas,
# matplotlib, Dask, Ray, pytest), builds the `filippov` module into it with maturin (release:
# the ensembles' tests run ten thousand runs three ways), and, with cargo's tests, the Rust
# side the Python tests compare against (examples/python_reference.rs), and runs pytest on
# python/tests (which starts its own two-worker Dask cluster and a local Ray).
#
# Work that leaves a core idle overlaps other work: the virtual environment (mostly
# downloads) is made while cargo builds the tests, and the module's release build
# (target/release, its own build lock) runs while cargo runs them (many test binaries
# end on one long test, one core busy). Each background job's output goes to a log
# under target/python, printed if it fails.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

# Each phase's time is printed at its end (the CI log keeps them).
phase() { echo "scripts/test.sh: $1 in $((SECONDS - start)) s"; start=$SECONDS; }
# `wait_for PID LOG WHAT`: the background job's status; its log on failure.
wait_for() {
    if ! wait "$1"; then
        echo "scripts/test.sh: $3 failed:" >&2
        cat "$2" >&2
        exit 1
    fi
}
# A fresh build gains nothing from incremental compilation's caches and pays for writing
# them; a caller who wants them can set CARGO_INCREMENTAL=1.
export CARGO_INCREMENTAL=${CARGO_INCREMENTAL:-0}
# A failure leaves no build running behind it.
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT
start=$SECONDS
logs=$root/target/python
mkdir -p "$logs"

venv=$root/target/python/venv
(
    if [ ! -x "$venv/bin/python" ]; then
        python3 -m venv "$venv"
    fi
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        -r python/requirements-test.txt
) > "$logs/venv.log" 2>&1 &
venv_job=$!

# The Python glue and the wheel are built (optimised) by maturin below; built here too
# they would only compile PyO3 twice. This build includes the examples, among them the
# Rust side of the Python tests (target/debug/examples/python_reference: the macros'
# compile tests turn on the facade's `urdf` feature it requires). Built again by itself
# with `--features urdf`, it would resolve the features differently and compile the
# facade and the runtime a second time.
cargo test --workspace --exclude filippov-python --exclude filippov-wheel --no-run
if [ ! -x target/debug/examples/python_reference ]; then
    echo "scripts/test.sh: cargo's test build made no target/debug/examples/python_reference" \
        "(it requires the facade's urdf feature)" >&2
    exit 1
fi
phase "cargo's tests built"
wait_for $venv_job "$logs/venv.log" "making the virtual environment"
phase "the virtual environment waited for"

(cd python/wheel && VIRTUAL_ENV=$venv PATH="$venv/bin:$PATH" maturin develop --quiet --release) \
    > "$logs/module.log" 2>&1 &
module_job=$!
cargo test --workspace --exclude filippov-python --exclude filippov-wheel
phase "cargo's tests run (the module building beside them)"
wait_for $module_job "$logs/module.log" "building the module"
phase "the module's build waited for"
"$venv/bin/python" -m pytest python/tests -q
phase "pytest run"
