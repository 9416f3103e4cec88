#!/usr/bin/env bash
# SPHinXsys side by side with shearsph on plane Poiseuille flow from rest.
#
# Builds SPHinXsys from SRC (a source tree, e.g. a clone, or a .tar.gz of one
# such as shared/peers/sphinxsys-9f33297.tar.gz) with the matched case written
# in this project, bench/peers/sphinxsys/shearsph_poiseuille_match/ (the stock
# test_2d_poiseuille_flow's methods: Wendland C2, h = 1.3 dx, square lattice,
# periodic in x, dual time stepping; parameterised by the half-width in
# particles, Re, c0 and the end time), then runs it and `shearsph bench
# --sphinxsys-match` alternately on 1 and 2 threads, and ladders both over
# resolution to the same t nu / B^2. Prints throughputs (particle-steps per
# second of the time-step loop alone), their ratio, both L_inf errors of the
# row-mean velocity against the start-up series (a fraction of U, the steady
# centre-line speed; the metric of bench/peers/peer_metric.py, which shearsph
# computes the same way), each ladder, and the wall time each code needs to
# reach common accuracies (peer_summary.py). Results, the ladder CSV and its
# chart go to OUT.
#
# usage: bench/peers/sphinxsys_poiseuille.sh SRC [ROUNDS=3] [TAU=1]
#
# The matched scene (both codes): U B / nu = RE (7.5, the stock case's Re = 10
# on the mean speed and the full width), c0 = C0_FACTOR U (10, the stock c_f =
# 10 x 1.5 U_f), B = LAYERS particle spacings (10, the stock dx = DH / 20), to
# t nu / B^2 = TAU (1: t = 2.5 in the stock case's units, whose own run goes
# to t = 100, t nu / B^2 = 40). The matched rounds use the stock channel
# length 6 DH on both sides (COLUMNS = 120 at 10 layers: SPHinXsys 2400 fluid
# + 1024 wall particles, the stock case exactly but for its end time;
# shearsph `--columns 120`, its own rows and wall layers on the same
# channel); the ladders use a strip of LADDER_COLUMNS_PER_LAYER x LAYERS
# columns on both sides (shearsph never narrower than its kernel allows).
#
# shearsph's side needs `shearsph bench --sphinxsys-match` (a square lattice
# and h = 1.3 d with the Wendland C2 kernel: not yet in shearsph when this
# script was written). It is called as
#   shearsph bench --sphinxsys-match --layers N --tau TAU --threads K --columns C
# and must print one JSON line with at least: code (starting "shearsph"),
# layers, particles, steps, threads, wall_s, particle_steps_per_s, t, tau
# (t nu / B^2 reached) and linf_rel_err; if it also prints re (U B / nu) and
# c0_over_u, they are checked against RE and C0_FACTOR. A binary without the
# flag stops the script with an error, unless SHEARSPH=0 (SPHinXsys alone).
#
# environment:
#   OUT             results (default target/peers/sphinxsys-tauTAU; files
#                   replaced whole, nothing else there touched)
#   SHEARSPH=0      run SPHinXsys alone
#   THREADS_LIST    thread counts (default "1 2")
#   LAYERS, RE, C0_FACTOR, COLUMNS   the matched scene (defaults above)
#   SPHINXSYS_LAYERS, SHEARSPH_LAYERS  the ladders (half-width in particles;
#                   defaults "5 6 8 10 14 20" and "4 5 6 8 10 14 20 28")
#   LADDER_COLUMNS_PER_LAYER  SPHinXsys's strip in the ladders (default 2:
#                   a strip of 2 N columns, 1 DH long)
#   VISCOUS         shearsph's viscous term: none (default, the paper's
#                   Laplacian) or lattice (its correction of the lattice's
#                   viscous deficit, as SPHinXsys corrects its gradients)
#   CFL             shearsph's CFL factor (default 0.5, the factor the peer
#                   figures were measured at; `default`: the kernel's own,
#                   0.898 here, as a run takes it)
#   LADDER=0        skip the ladders
#   TARGETS         Linf/U targets for the time to accuracy
#   PEERS_CACHE     build cache (default ~/.cache/shearsph-peers)
#   PEERS_NICE      niceness of the build (default 19)
#   SPHINXSYS_CXX_FLAGS  extra compiler flags (default none: the stock
#                   Release flags, -O3, for the generic x86-64 target)
#   NO_APT=1        do not install missing Debian packages, only name them
#
# The build (cmake, make of the library and the one case) goes into
# PEERS_CACHE/sphinxsys-KEY, KEY from the tarball's hash or the tree's path;
# later runs reuse it and make rebuilds only what changed (a source tree is
# mirrored there with its timestamps, so SRC itself is never written to).
# The first build takes 12-40 minutes on 2 cores (see README.md).
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
die() { echo "sphinxsys_poiseuille: $*" >&2; exit 1; }

[ $# -ge 1 ] || die "usage: $0 SRC [ROUNDS=3] [TAU=1] (SRC: a SPHinXsys source tree or .tar.gz)"
SRC=$1
ROUNDS=${2:-3}
TAU=${3:-1}
THREADS_LIST=${THREADS_LIST:-1 2}
LAYERS=${LAYERS:-10}
RE=${RE:-7.5}
C0_FACTOR=${C0_FACTOR:-10}
COLUMNS=${COLUMNS:-$((12 * LAYERS))}
SPHINXSYS_LAYERS=${SPHINXSYS_LAYERS:-5 6 8 10 14 20}
SHEARSPH_LAYERS=${SHEARSPH_LAYERS:-4 5 6 8 10 14 20 28}
LADDER_COLUMNS_PER_LAYER=${LADDER_COLUMNS_PER_LAYER:-2}
LADDER=${LADDER:-1}
SHEARSPH=${SHEARSPH:-1}
VISCOUS=${VISCOUS:-none}
CFL=${CFL:-0.5}
CACHE=${PEERS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/shearsph-peers}
NICE=${PEERS_NICE:-19}
OUT=${OUT:-$ROOT/target/peers/sphinxsys-tau$TAU}
CASE_NAME=shearsph_poiseuille_match
CASE_DIR="$HERE/sphinxsys/$CASE_NAME"

# ---- Debian packages ------------------------------------------------------
PKGS=(cmake g++ libsimbody-dev libeigen3-dev libtbb-dev libboost-dev
      libboost-program-options-dev libspdlog-dev libgtest-dev)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${NO_APT:-0}" = 1 ] || [ "$(id -u)" != 0 ] || ! command -v apt-get > /dev/null; then
    die "missing Debian packages: ${missing[*]}; install them (apt-get install ${missing[*]}) and run again"
  fi
  echo "sphinxsys_poiseuille: installing ${missing[*]}" >&2
  DEBIAN_FRONTEND=noninteractive nice -n "$NICE" apt-get install -y -qq "${missing[@]}" >&2 \
    || die "apt-get install ${missing[*]} failed (run apt-get update first?)"
fi

# ---- Sources: mirrored into the cache --------------------------------------
if [ -f "$SRC" ]; then
  case "$SRC" in *.tar.gz|*.tgz) ;; *) die "SRC $SRC: a file must be a .tar.gz of a SPHinXsys tree" ;; esac
  KEY=$(sha256sum "$SRC" | cut -c1-12)
elif [ -d "$SRC" ]; then
  SRC=$(cd "$SRC" && pwd)
  [ -f "$SRC/CMakeLists.txt" ] && [ -d "$SRC/src/shared" ] && [ -d "$SRC/tests/2d_examples" ] \
    || die "SRC $SRC: not a SPHinXsys source tree (needs CMakeLists.txt, src/shared/, tests/2d_examples/)"
  KEY=$(printf '%s' "$SRC" | sha256sum | cut -c1-12)
else
  die "SRC $SRC: no such file or directory"
fi
BUILD_ROOT="$CACHE/sphinxsys-$KEY"
MIRROR="$BUILD_ROOT/src"
BUILD="$BUILD_ROOT/build"
mkdir -p "$MIRROR" "$BUILD"
if [ -f "$SRC" ]; then
  if [ ! -f "$BUILD_ROOT/.extracted" ]; then
    # A tarball holds one top folder (SPHinXsys/) or the tree itself.
    tar -tzf "$SRC" > "$BUILD_ROOT/.listing"
    top=$(sed -n 1p "$BUILD_ROOT/.listing" | cut -d/ -f1)
    strip=0
    if grep -qx "$top/CMakeLists.txt" "$BUILD_ROOT/.listing"; then strip=1; fi
    tar -xzf "$SRC" -C "$MIRROR" --strip-components="$strip"
    [ -f "$MIRROR/CMakeLists.txt" ] || die "SRC $SRC: no CMakeLists.txt at the top of the archive"
    touch "$BUILD_ROOT/.extracted"
  fi
else
  # Timestamps kept, so make rebuilds only what changed in SRC.
  tar -C "$SRC" --exclude=.git --exclude=./build -cf - . | tar -C "$MIRROR" -xf -
fi
# The matched case, copied in only when it differs (its timestamp kept).
mkdir -p "$MIRROR/tests/2d_examples/$CASE_NAME"
for f in "$CASE_DIR"/*; do
  dst="$MIRROR/tests/2d_examples/$CASE_NAME/$(basename "$f")"
  cmp -s "$f" "$dst" 2>/dev/null || cp -p "$f" "$dst"
done

# ---- Configure and build ---------------------------------------------------
CMAKE_ARGS=(-DCMAKE_BUILD_TYPE=Release -DSPHINXSYS_3D=OFF
  -DSPHINXSYS_BUILD_3D_EXAMPLES=OFF -DSPHINXSYS_BUILD_EXTRA_SOURCE_AND_TESTS=OFF
  -DSPHINXSYS_BUILD_MODULES=OFF -DSPHINXSYS_BUILD_OPTIMIZATION_EXAMPLES=OFF
  -DSPHINXSYS_BUILD_PYTHON_INTERFACE=OFF -DSPHINXSYS_BUILD_UNIT_TESTS=OFF
  -DSPHINXSYS_DEVELOPER_MODE=OFF "-DCMAKE_CXX_FLAGS=${SPHINXSYS_CXX_FLAGS:-}")
if [ ! -f "$BUILD/CMakeCache.txt" ] || [ "$(cat "$BUILD_ROOT/.cmake-args" 2>/dev/null)" != "${CMAKE_ARGS[*]}" ] \
   || [ ! -f "$BUILD/tests/2d_examples/$CASE_NAME/Makefile" ]; then
  echo "sphinxsys_poiseuille: configuring in $BUILD" >&2
  (cd "$BUILD" && nice -n "$NICE" cmake "$MIRROR" "${CMAKE_ARGS[@]}" > "$BUILD_ROOT/configure.log" 2>&1) \
    || die "cmake failed: see $BUILD_ROOT/configure.log"
  printf '%s' "${CMAKE_ARGS[*]}" > "$BUILD_ROOT/.cmake-args"
fi
echo "sphinxsys_poiseuille: building $CASE_NAME in $BUILD (make -j$(nproc), nice $NICE)" >&2
start=$(date +%s)
(cd "$BUILD" && nice -n "$NICE" make -j"$(nproc)" "$CASE_NAME" > "$BUILD_ROOT/build.log" 2>&1) \
  || die "make failed: see $BUILD_ROOT/build.log"
took=$(( $(date +%s) - start ))
echo "$(date -u +%FT%TZ) make $CASE_NAME: ${took} s" >> "$BUILD_ROOT/build-times.log"
echo "sphinxsys_poiseuille: build done in ${took} s (history in $BUILD_ROOT/build-times.log)" >&2
CASE_BIN=$(find "$BUILD/tests/2d_examples/$CASE_NAME" -type f -name "$CASE_NAME" -perm -u+x | head -n 1)
[ -n "$CASE_BIN" ] || die "built, but no $CASE_NAME binary under $BUILD/tests/2d_examples/$CASE_NAME"

# ---- shearsph -------------------------------------------------------------
if [ "$SHEARSPH" != 0 ]; then
  (cd "$ROOT" && cargo build --release --quiet)
  BIN="$ROOT/target/release/shearsph"
  "$BIN" bench --help 2>/dev/null | grep -q -- "--sphinxsys-match" \
    || die "$BIN has no \`bench --sphinxsys-match\` (it needs shearsph's square lattice and h = 1.3 d with \
the Wendland C2 kernel, issue 16); run with SHEARSPH=0 to run SPHinXsys alone"
fi

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$OUT" "$WORK/run"
sphinxsys() {
  # sphinxsys THREADS LAYERS COLUMNS: one run, its JSON with the error added.
  # It runs in a scratch folder: SPHinXsys creates output/ and reload/ there.
  (cd "$WORK/run" && "$CASE_BIN" --layers "$2" --re "$RE" --c0-factor "$C0_FACTOR" --tau "$TAU" \
      --columns "$3" --threads "$1") | tail -n 1 | python3 "$HERE/peer_metric.py"
}
shearsph() {
  # shearsph THREADS LAYERS COLUMNS (at least the narrowest strip the kernel
  # allows: 6 columns for Wendland C2 at h = 1.3 d)
  local line cols=$3
  [ "$cols" -ge 6 ] || cols=6
  line=$("$BIN" bench --sphinxsys-match --layers "$2" --tau "$TAU" --threads "$1" --columns "$cols" \
      --viscous-normalisation "$VISCOUS" --cfl "$CFL")
  python3 - "$RE" "$C0_FACTOR" "$line" <<'PYEOF'
import json, sys
re_, c0f, run = float(sys.argv[1]), float(sys.argv[2]), json.loads(sys.argv[3])
for key, want in (("re", re_), ("c0_over_u", c0f)):
    if key in run and abs(run[key] - want) > 1e-9 * want:
        sys.exit(f"sphinxsys_poiseuille: shearsph's scene has {key} = {run[key]}, the SPHinXsys case {want}")
print(json.dumps(run))
PYEOF
}
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)

# A short untimed run of each first (page cache, TBB and rayon start-up).
for t in $THREADS_LIST; do
  TAU_SAVED=$TAU; TAU=0.01
  sphinxsys "$t" "$LAYERS" "$COLUMNS" > /dev/null
  [ "$SHEARSPH" = 0 ] || shearsph "$t" "$LAYERS" "$COLUMNS" > /dev/null
  TAU=$TAU_SAVED
done

: > "$WORK/sphinxsys.jsonl"
: > "$WORK/shearsph.jsonl"
for r in $(seq "$ROUNDS"); do
  for t in $THREADS_LIST; do
    echo "round $r/$ROUNDS, $t thread(s): sphinxsys, $LAYERS layers, $COLUMNS columns, to t nu/B^2 = $TAU" >&2
    sphinxsys "$t" "$LAYERS" "$COLUMNS" >> "$WORK/sphinxsys.jsonl"
    if [ "$SHEARSPH" != 0 ]; then
      echo "round $r/$ROUNDS, $t thread(s): shearsph, $LAYERS layers, $COLUMNS columns" >&2
      shearsph "$t" "$LAYERS" "$COLUMNS" >> "$WORK/shearsph.jsonl"
    fi
  done
done

: > "$WORK/ladder.jsonl"
if [ "$LADDER" != 0 ]; then
  read -r -a SX <<< "$SPHINXSYS_LAYERS"
  read -r -a SH <<< "$SHEARSPH_LAYERS"
  n=$(( ${#SX[@]} > ${#SH[@]} ? ${#SX[@]} : ${#SH[@]} ))
  for t in $THREADS_LIST; do
    for ((i = 0; i < n; i++)); do
      if [ "$i" -lt "${#SX[@]}" ]; then
        echo "ladder, $t thread(s): sphinxsys, ${SX[$i]} layers" >&2
        sphinxsys "$t" "${SX[$i]}" $(( LADDER_COLUMNS_PER_LAYER * SX[i] )) >> "$WORK/ladder.jsonl"
      fi
      if [ "$SHEARSPH" != 0 ] && [ "$i" -lt "${#SH[@]}" ]; then
        echo "ladder, $t thread(s): shearsph, ${SH[$i]} layers" >&2
        shearsph "$t" "${SH[$i]}" $(( LADDER_COLUMNS_PER_LAYER * SH[i] )) >> "$WORK/ladder.jsonl"
      fi
    done
  done
fi
LOAD_AFTER=$(cut -d' ' -f1-3 /proc/loadavg)

NOTE="machine: $(nproc) cores; load average (1, 5, 15 min) before $LOAD_BEFORE, after $LOAD_AFTER"
NOTE="$NOTE (above about 0.3 other work was running: the timings are then indicative only)"
NOTE="$NOTE
strips: the matched rounds $COLUMNS columns on both sides (the stock channel; the particle counts \
differ by each code's rows and wall layers, printed per round), the ladders $LADDER_COLUMNS_PER_LAYER x \
the half-width in particles on both sides (shearsph at least 6)
SPHinXsys: $(basename "$SRC"), built with the stock Release flags${SPHINXSYS_CXX_FLAGS:+ plus $SPHINXSYS_CXX_FLAGS}; \
steps are its acoustic steps (about 5 per advection step, which alone rebuilds the neighbour lists \
and evaluates density, viscous force and transport correction)
shearsph: the paper's WCSPH, one density and one force pass per step; viscous term: $VISCOUS; \
CFL factor: $CFL"
SUMMARY_ARGS=(--peer "$WORK/sphinxsys.jsonl" --load "$NOTE")
[ -s "$WORK/shearsph.jsonl" ] && SUMMARY_ARGS+=(--ours "$WORK/shearsph.jsonl")
[ -s "$WORK/ladder.jsonl" ] && SUMMARY_ARGS+=(--ladder "$WORK/ladder.jsonl" --csv "$OUT/ladder.csv")
[ -n "${TARGETS:-}" ] && SUMMARY_ARGS+=(--targets "$TARGETS")
python3 "$HERE/peer_summary.py" "${SUMMARY_ARGS[@]}" | tee "$WORK/summary.txt"
VENV=${PYSPH_VENV:-$CACHE/pysph-1.0b2}
if [ -s "$WORK/ladder.jsonl" ]; then
  if "$VENV/bin/python" -c "import matplotlib" 2> /dev/null; then
    "$VENV/bin/python" "$HERE/peer_chart.py" "$OUT/ladder.csv" "$OUT/ladder.png" \
      "SPHinXsys and shearsph, Poiseuille start-up to t nu/B^2 = $TAU" \
      "load average before $LOAD_BEFORE, after $LOAD_AFTER (above about 0.3: indicative only)"
  else
    echo "sphinxsys_poiseuille: no chart (matplotlib comes with the PySPH venv: bench/peers/pysph_setup.sh)" >&2
  fi
fi
for f in sphinxsys.jsonl shearsph.jsonl ladder.jsonl summary.txt; do  # ladder.csv, .png: written in place, atomically
  if [ -s "$WORK/$f" ]; then
    cp "$WORK/$f" "$OUT/.$f.tmp" && mv "$OUT/.$f.tmp" "$OUT/$f"
  fi
done
echo "results in $OUT" >&2
