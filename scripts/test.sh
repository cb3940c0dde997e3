#!/usr/bin/env bash
# The tests, on a fresh machine with a Rust toolchain and Python 3: cargo's tests, then
# the Python module's. It makes its own virtual environment (target/python/venv),
# installs python/requirements-test.txt into it from PyPI (maturin, NumPy, pandas,
# matplotlib, Dask, Ray, pytest), builds the `filippov` module into it with maturin (release:
# the ensembles' tests run ten thousand runs three ways), builds the Rust side the
# Python tests compare against (examples/python_reference.rs), and runs pytest on
# python/tests (which starts its own two-worker Dask cluster and a local Ray).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

# The Python glue and the wheel are built (optimised) by maturin below; built here too
# they would only compile PyO3 twice.
cargo test --workspace --exclude filippov-python --exclude filippov-wheel

venv=$root/target/python/venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
(cd python/wheel && VIRTUAL_ENV=$venv PATH="$venv/bin:$PATH" maturin develop --quiet --release)
# Already built by `cargo test` (same profile and features); a no-op then.
cargo build --quiet --profile test --features urdf --example python_reference
"$venv/bin/python" -m pytest python/tests -q
