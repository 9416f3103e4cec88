#!/usr/bin/env python3
"""Effective viscosity of a steady `shearsph run` from its profile (bench/peers/ACCURACY.md).

In the steady state the interior satisfies nu_eff u'' = -p whatever the walls
do (the wall model moves only the level of the parabola), so a least-squares
fit u = a + b y^2 over the layers at least MARGIN d (default: 3 d, beyond
R h = 2.6 d of Wendland C2 at h = 1.3 d) from the walls gives
nu_eff / nu = (2 U / B^2) / (-2 b) = -U / (B^2 b), and a / U the centre-line
speed the interior curvature and the walls give together.

usage: scripts/profile_fit.py RUN_DIR [MARGIN]   (RUN_DIR holds summary.json and profile.csv)
"""
import csv
import json
import sys


def main():
    run = sys.argv[1]
    margin = float(sys.argv[2]) if len(sys.argv) > 2 else 3.0
    s = json.load(open(f"{run}/summary.json"))
    b_half, u, d = s["b"], s["u"], s["d"]
    rows = list(csv.DictReader(open(f"{run}/profile.csv")))
    pts = [(float(r["y"]), float(r["u"])) for r in rows if abs(float(r["y"])) <= b_half - margin * d]
    # least squares for u = a + b y^2
    n = len(pts)
    sx = sum(y * y for y, _ in pts)
    sxx = sum(y ** 4 for y, _ in pts)
    sy = sum(v for _, v in pts)
    sxy = sum(y * y * v for y, v in pts)
    bcoef = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    a = (sy - bcoef * sx) / n
    nu_ratio = -u / (b_half * b_half * bcoef)
    print(json.dumps({
        "run": run, "layers_fitted": n, "nu_eff_over_nu": round(nu_ratio, 6),
        "u_centre_over_u": round(a / u, 6), "linf_rel_err": s["linf_rel_err"],
        "t_nu_over_b2": s["t"] * s["nu"] / b_half ** 2,
    }))


if __name__ == "__main__":
    main()
