#!/usr/bin/env bash
# Peer measurements for the report: Pinocchio, SciPy, SymPy, SUNDIALS IDA (scikit-sundae) and MuJoCo in a virtual environment
# cached at target/peers/venv (PEERS_VENV overrides it). Writes target/report/peers/
# peers.md and peers.tsv (the report embeds them). The report runs this script itself
# before its sections (unless --no-peers); by hand it needs the exported models first.
# diffsol is not run here: the report builds and runs peers/diffsol itself (its README).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(dirname "$HERE")"
OUT="$ROOT/target/report/peers"
MODELS="$ROOT/target/report/models"
BUILD="$OUT/build"
RES="$OUT/results"
# The virtual environment is cached under target/ (the report runs this script itself).
VENV="${PEERS_VENV:-$ROOT/target/peers/venv}"
PY="$VENV/bin/python"

fail() { echo "peers/run.sh: FAILED: $*" >&2; exit 1; }
trap 'echo "peers/run.sh: FAILED at line $LINENO: $BASH_COMMAND" >&2' ERR

for s in double_pendulum planar_arm3 branched_tree panda; do
  [ -f "$MODELS/$s.json" ] || fail "missing $MODELS/$s.json; run 'cargo run --release --example report -- --no-compile' first"
done
command -v python3 >/dev/null || fail "python3 not found"
command -v gcc >/dev/null || fail "gcc not found (needed for the SymPy harness)"

# 1. virtual environment with pinned versions
if [ ! -x "$PY" ]; then
  echo "== creating $VENV"
  python3 -m venv "$VENV" || fail "python3 -m venv failed (Debian: apt-get install python3-venv)"
fi
echo "== pip install -r peers/requirements.txt"
"$PY" -m pip install -q --disable-pip-version-check -r "$HERE/requirements.txt" || fail "pip install failed"
"$PY" -c "import pinocchio, scipy, sympy, numpy" || fail "the installed packages do not import"

rm -rf "$RES" "$OUT/peers.md" "$OUT/peers.tsv" "$OUT/ida_andrews.tsv" "$OUT/mujoco_contacts.tsv"
mkdir -p "$BUILD" "$RES"

VERSIONS="$("$PY" -c "import pinocchio, scipy, sympy, numpy, platform; print(f'Python {platform.python_version()}, pin {pinocchio.__version__}, numpy {numpy.__version__}, scipy {scipy.__version__}, sympy {sympy.__version__}')")"
GCCV="$(gcc -dumpfullversion 2>/dev/null || gcc -dumpversion)"
CPU="$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)"
MACHINE="nproc $(nproc), CPU ${CPU:-unknown}, $(uname -sm)"
# Two builds of the C++ benchmark: for the baseline x86-64 target (no -march, as rustc's
# default release build of ours; the one pin_bench.py and the report's URDF section use)
# and for this machine (-march=native, the report's section on CPU flags).
CXXFLAGS="-std=c++17 -O3 -DNDEBUG"
NATIVE="-march=native"

# 2a. Pinocchio: C++ benchmark against the wheel's headers (fallback: Python bindings)
PREFIX="$("$PY" -c "import site; print(site.getsitepackages()[0])")/cmeel.prefix"
BIN="$BUILD/pin_bench"
for flavour in baseline native; do
  if [ "$flavour" = native ]; then out="$BIN"_native; flags="$CXXFLAGS $NATIVE"; else out="$BIN"; flags="$CXXFLAGS"; fi
  if [ ! -x "$out" ] || [ "$HERE/pin_bench.cpp" -nt "$out" ] || [ "$HERE/requirements.txt" -nt "$out" ]; then
    echo "== compiling peers/pin_bench.cpp ($flavour: $flags) against $PREFIX/include (a few minutes)"
    if ! g++ $flags -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
        -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
        -I"$PREFIX/include" -I"$PREFIX/include/eigen3" "$HERE/pin_bench.cpp" -o "$out" 2> "$BUILD/pin_bench_$flavour.log"; then
      echo "peers/run.sh: warning: C++ build ($flavour) failed (see $BUILD/pin_bench_$flavour.log)" >&2
      rm -f "$out"
    fi
  fi
done
[ -x "$BIN" ] || echo "peers/run.sh: warning: no baseline C++ build; timing the Python bindings instead" >&2
echo "== Pinocchio"
"$PY" "$HERE/pin_bench.py" "$MODELS" "$BUILD" "$RES/pinocchio.json" "$( [ -x "$BIN" ] && echo "$BIN" || echo "")" \
  || fail "Pinocchio benchmark failed"

# 2a'. Pinocchio on the URDF robots (robots/*.urdf), at the states the report exported
if ls "$ROOT/target/report/urdf/"*.json >/dev/null 2>&1; then
  echo "== Pinocchio on the URDF robots"
  "$PY" "$HERE/urdf_pin.py" "$ROOT/target/report/urdf" "$OUT/urdf.tsv" "$( [ -x "$BIN" ] && echo "$BIN" || echo "")" \
    || fail "URDF comparison failed"
fi

# 2b. SciPy
echo "== SciPy"
"$PY" "$HERE/scipy_bench.py" "$RES/scipy.json" > "$BUILD/scipy.log" || { cat "$BUILD/scipy.log"; fail "SciPy benchmark failed"; }

# 2b'. SUNDIALS IDA on Andrews' squeezer (the report's section on closed loops reads it)
echo "== IDA (scikit-sundae) on Andrews' squeezer"
"$PY" "$HERE/ida_andrews.py" "$OUT/ida_andrews.tsv" > "$BUILD/ida_andrews.log" 2>&1 \
  || { cat "$BUILD/ida_andrews.log"; echo "peers/run.sh: warning: the IDA peer failed (see $BUILD/ida_andrews.log)" >&2; }

# 2b''. MuJoCo on the contact scenes (the report's section on contacts reads it)
echo "== MuJoCo on the contact scenes"
"$PY" "$HERE/mujoco_contacts.py" "$OUT/mujoco_contacts.tsv" > "$BUILD/mujoco_contacts.log" 2>&1 \
  || { cat "$BUILD/mujoco_contacts.log"; echo "peers/run.sh: warning: the MuJoCo peer failed (see $BUILD/mujoco_contacts.log)" >&2; }

# 2c. SymPy chains n = 2..7, stop once a derivation takes more than 120 s
echo "== SymPy"
: > "$RES/sympy_note.txt"
for n in 2 3 4 5 6 7; do
  if ! timeout 600 "$PY" "$HERE/sympy_chain.py" "$n" "$BUILD" "$RES/chain$n.json"; then
    echo "The sweep stopped at n = $n: its derivation + codegen did not finish within 600 s (or failed)." > "$RES/sympy_note.txt"
    break
  fi
  if "$PY" -c "import json,sys; sys.exit(0 if json.load(open('$RES/chain$n.json'))['derive_s'] > 120 else 1)"; then
    [ "$n" -lt 7 ] && echo "The sweep stopped after n = $n: its derivation took more than 120 s." > "$RES/sympy_note.txt"
    break
  fi
done

# 3. tables
"$PY" - "$RES/header.json" <<PYEOF
import json, sys, datetime
json.dump({"date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
           "machine": """$MACHINE""", "versions": """$VERSIONS, gcc $GCCV""", "cxxflags": """$CXXFLAGS (and $NATIVE for pin_bench_native)"""},
          open(sys.argv[1], "w"))
PYEOF
"$PY" "$HERE/collect.py" "$OUT" "$RES/header.json" || fail "writing the tables failed"
[ -s "$OUT/peers.md" ] && [ -s "$OUT/peers.tsv" ] || fail "peers.md / peers.tsv missing"
echo "== wrote $OUT/peers.md and $OUT/peers.tsv"
