"""The accuracy metric every peer comparison in bench/peers/ uses, in one
place: the L_inf norm over rows (layers) of the mean x velocity minus the
start-up series of plane Poiseuille flow at the time reached, divided by the
centre-line speed of the steady profile (shearsph computes the same in Rust,
`linf_rel_err` of `shearsph bench --pysph-match`).

As a script: reads JSON lines with a `profile` ([[y, mean u, count], ...],
y from the lower wall) and `t`, `ly`, `fx`, `nu`, `u` (the steady centre-line
speed), as bench/peers/sphinxsys/'s case prints them, and writes each back
with `linf_rel_err` added and the profile summarised.

usage: python3 peer_metric.py < RUNS.jsonl > RUNS-WITH-ERRORS.jsonl
"""
import json
import math
import sys


def startup(y, t, ly, fx, nu, tol=1e-15):
    """u(y, t) from rest between walls at y = 0 and ly under the body force fx
    (Morris, Fox & Zhu 1997), the series summed until the rest is below tol."""
    amp = 4.0 * fx * ly * ly / (nu * math.pi ** 3)
    tau = math.pi ** 2 * nu * t / (ly * ly)
    u = fx / (2.0 * nu) * y * (ly - y)
    k = 1.0
    while True:
        term = amp / k ** 3 * math.exp(-k * k * tau)
        u -= term * math.sin(k * math.pi * y / ly)
        if term < tol * fx / (2.0 * nu) * ly * ly / 4.0 or k > 1e6:
            return u
        k += 2.0


def linf_rel_err(rows, t, ly, fx, nu, u_max):
    """rows: (mean y, mean u) per row; the largest |mean u - u(mean y, t)| / u_max."""
    return max(abs(u - startup(float(y), t, ly, fx, nu)) / u_max for y, u in rows)


def main():
    for line in sys.stdin:
        if not line.strip():
            continue
        run = json.loads(line)
        rows = [(y, u) for y, u, n in run["profile"] if n]
        run["linf_rel_err"] = linf_rel_err(rows, run["t"], run["ly"], run["fx"], run["nu"], run["u"])
        run["rows_filled"] = len(rows)
        run["rows"] = len(run["profile"])
        del run["profile"]
        print(json.dumps(run))


if __name__ == "__main__":
    main()
