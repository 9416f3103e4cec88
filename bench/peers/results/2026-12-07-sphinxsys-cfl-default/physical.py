"""Per unit of physical time, from each run's summary.txt (its last line,
JSON): particles x t nu / B^2 reached per wall second of the median
round, both codes, 1 and 2 threads; the per-step ratio beside it; and the
wall time to SPHinXsys's matched error (interpolated on the ladders).

usage: physical.py RUN_DIR...   (each written by sphinxsys_poiseuille.sh)
"""
import json
import os
import sys


def per_time(run):
    return run["particles"] * run["tau"] / run["median_wall_s"]


print(f"{'run':34} thr  cfl     steps  Linf/U     sphinxsys  shearsph  "
      "per time  per step  to the first target (interp.)")
for d in sys.argv[1:]:
    with open(os.path.join(d, "summary.txt")) as f:
        summary = json.loads(f.read().strip().splitlines()[-1])
    targets = summary.get("to_accuracy", [])
    for thr, rnd in sorted(summary["rounds"].items()):
        sx, sh = rnd["sphinxsys"], rnd["shearsph"]
        ratio_time = per_time(sh) / per_time(sx)
        to = ""
        if targets:
            walls = {(c["code"], c["threads"]): c.get("interpolated_wall_s")
                     for c in targets[0]["codes"]}
            a, b = walls.get(("sphinxsys", int(thr))), walls.get(("shearsph", int(thr)))
            if a and b:
                to = f"{a / b:.1f}x ({targets[0]['target']:.3e} U)"
        print(f"{os.path.basename(d):34} {thr:>3}  {sh.get('cfl', 0.5):.4f} {sh['steps']:6d}"
              f"  {sh['median_linf_rel_err']:.3e}  {per_time(sx):9.0f} {per_time(sh):9.0f}"
              f"  {ratio_time:7.2f}x  {rnd['ratio']:7.2f}x  {to}")
