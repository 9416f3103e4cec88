#!/usr/bin/env bash
# Install PySPH 1.0b2 (PyPI `pysph`) into a virtual environment, on a fresh
# machine with Python 3.11 and a C compiler (with OpenMP: gcc). Idempotent: a
# finished install leaves a marker and is reused. Prints the venv's path.
# PYSPH_VENV chooses it (default ~/.cache/shearsph-peers/pysph-1.0b2).
# The build (a few minutes of C++ compilation) runs under `nice -n 19`, so that
# it takes only idle CPU on a shared machine; PEERS_NICE sets the niceness.
#
# What makes 1.0b2 build here (each step is needed, found by trying):
# - Cython 3 fails on pysph/base/box_sort_nnps.pyx: pin cython<3.
# - Its build needs numpy, cyarray and compyle importable at build time, so
#   everything is installed with --no-build-isolation (the sdist's own
#   pyproject asks for numpy>=2, which its Cython 0.29 sources do not build with).
# - The OpenCL extensions (pysph/base/*gpu*.pyx) do not compile against
#   numpy's current headers (`PyArrayObject has no member named data`) and
#   need pyopencl anyway: they are dropped from setup.py. The CPU solver with
#   OpenMP does not use them.
set -euo pipefail

VENV=${PYSPH_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/shearsph-peers/pysph-1.0b2}
PY=${PYTHON:-python3}
MARK="$VENV/.pysph-1.0b2-ok"

# matplotlib draws the peer comparisons' ladder chart (peer_chart.py); a venv
# made before it was added gets it here. numpy stays at the version PySPH
# was built against.
matplotlib() {
  "$VENV/bin/python" -c "import matplotlib" 2> /dev/null ||
    nice -n "${PEERS_NICE:-19}" "$VENV/bin/python" -m pip install --quiet "matplotlib" "numpy>=1.23,<1.25" >&2
}

if [ -f "$MARK" ]; then
  echo "pysph_setup: reusing $VENV" >&2
  matplotlib
  echo "$VENV"
  exit 0
fi

echo "pysph_setup: creating $VENV" >&2
rm -rf "$VENV"
"$PY" -m venv "$VENV"
PIP=(nice -n "${PEERS_NICE:-19}" "$VENV/bin/python" -m pip install --quiet)
exec 3>&1 1>&2  # everything but the final path goes to stderr

"${PIP[@]}" --upgrade "pip" "setuptools<70" "wheel"
"${PIP[@]}" "cython<3" "numpy>=1.23,<1.25" mako pytools beaker
"${PIP[@]}" --no-build-isolation cyarray compyle

SRC=$(mktemp -d)
trap 'rm -rf "$SRC"' EXIT
# The sdist (1.0b2 has no wheels); its metadata is prepared in this venv.
"$VENV/bin/python" -m pip download --quiet --no-deps --no-binary pysph \
  --no-build-isolation -d "$SRC" "pysph==1.0b2"
tar -xzf "$SRC"/pysph-1.0b2.tar.gz -C "$SRC"
"$VENV/bin/python" - "$SRC/pysph-1.0b2/setup.py" <<'PYEOF'
import sys
path = sys.argv[1]
text = open(path).read()
anchor = "    return ext_modules\n\n\ndef get_parallel_extensions"
assert anchor in text, "setup.py layout changed: cannot drop the OpenCL extensions"
text = text.replace(
    anchor,
    "    # shearsph peer run: no OpenCL extensions (see pysph_setup.sh)\n"
    "    ext_modules = [e for e in ext_modules if 'gpu' not in e.name]\n"
    + anchor,
)
open(path, "w").write(text)
PYEOF
( cd "$SRC/pysph-1.0b2" && "${PIP[@]}" --no-build-isolation --no-deps . )
"$VENV/bin/python" -c "import pysph, pysph.base.nnps, pysph.base.omp_threads; print('pysph', pysph.__version__)" >&2
matplotlib
touch "$MARK"
echo "$VENV" >&3
