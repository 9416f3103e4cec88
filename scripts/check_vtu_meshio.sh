#!/usr/bin/env bash
# Optional (not part of cargo test): a second reader agrees with vtkio.
# Writes a small run's particle series, then opens its last .vtu with
# Python's meshio (pip, in a venv under target/) and prints the particle
# count, the point arrays and a few values beside the run's summary.
# Usage: scripts/check_vtu_meshio.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/meshio-check}
venv=target/meshio-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c 'import meshio' 2>/dev/null || "$venv/bin/pip" install --quiet meshio
cargo run --release --quiet -- run --kernel monaghan --n 10 --out "$out" --force --quiet >/dev/null
"$venv/bin/python" - "$out" <<'PY'
import json, sys, xml.etree.ElementTree as ET
import meshio, numpy as np
out = sys.argv[1]
sets = ET.parse(f"{out}/particles.pvd").getroot().iter("DataSet")
last = list(sets)[-1]
m = meshio.read(f"{out}/{last.get('file')}")
s = json.load(open(f"{out}/summary.json"))
wall = m.point_data["wall"].astype(bool)
eps = m.point_data["eps"]
print(f"meshio {meshio.__version__} read {last.get('file')} (t = {last.get('timestep')})")
print(f"points: {len(m.points)} (summary: {s['particles']}), cells: {[c.type for c in m.cells]}")
print(f"point arrays: {list(m.point_data)}")
print(f"fluid: {(~wall).sum()} (summary: {s['fluid_particles']})")
print(f"mean fluid eps: {eps[~wall].mean():.15e} (summary: {s['mean_eps']:.15e})")
print(f"max fluid eps now: {eps[~wall].max():.6e}; velocity[0] = {m.point_data['velocity'][0]}")
PY
# Output of one run (2026-12-01, meshio 5.3.5):
#   meshio 5.3.5 read particles_00020.vtu (t = 243.56037629403332)
#   points: 115 (summary: 115), cells: ['vertex']
#   point arrays: ['velocity', 'density', 'pressure', 'eps', 'wall', 'layer']
#   fluid: 95 (summary: 95)
#   mean fluid eps: -1.415557318762508e-03 (summary: -1.415557318762508e-03)
#   max fluid eps now: 6.396418e-03; velocity[0] = [1.96084706e-01 3.52849565e-05 0.00000000e+00]
