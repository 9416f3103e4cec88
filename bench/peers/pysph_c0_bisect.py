"""PySPH's own c0_min for one scheme and Re, searched the way shearsph's
`c0 --empirical` searches its own (src/studies/empirical/search.rs): the smallest c0
whose jittered seeds, pooled (the mean of their eps_stat), do not
over-compress, eps_stat <= eps0 + 0.01; the seeds' mean linf_stat then
says whether that c0 is also accurate (ok) or not (inaccurate), as
shearsph's classes do.

The search, as shearsph's: from the first probe, steps by sqrt(10) up while
compressed (or down while not) to a bracket; then narrows it until
hi / lo <= 1 + rel_tol, each probe where the law through the two settled
trials nearest the bracket's middle (ln(eps_stat - eps0) linear in ln c0)
puts the bound, kept a factor 1 + rel_tol inside the bracket (within
(1 + rel_tol)^2, moved where either class closes it), or the geometric
middle when there is no such law. (Before 2026-12-05's change to
shearsph's search, both kept the law's probe a factor sqrt(1 + rel_tol)
inside the bracket; docs/validation.md's bisections ran so.) A trial is settled when
every seed ended disordered (dy_rms >= 0.1 d) in a stationary window of
shearsph's run of the same seed. Every probe runs `pysph_c0.sh` for its
seeds (a run already in OUT is reused), each PySPH run judged on shearsph's
window of the same scene and seed.

`--bracket LO HI` starts from two probes instead of from `--first` (both
probed like any other, seeds run where missing): the bracket a ladder
already gives. It is the one departure from shearsph's search, which starts
at 10 U; the narrowing is the same.

usage: python3 pysph_c0_bisect.py OUT --re RE --scheme matched|tvf|...
           [--first 10] [--bracket LO HI] [--rel-tol 0.1] [--seeds 3]
       prints the probes and the answer; writes OUT/bisect-SCHEME-reRE.json
       (env: as pysph_c0.sh's: SHEARSPH, JOBS, PEERS_NICE)
"""
import argparse
import json
import math
import os
import subprocess
import sys

import pysph_c0_table as table

HERE = os.path.dirname(os.path.abspath(__file__))


def c0_name(c):
    """The c0 as the runs' file names spell it (4 decimals, trailing zeros dropped)."""
    return ("%.4f" % c).rstrip("0").rstrip(".")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--re", type=float, required=True)
    ap.add_argument("--scheme", required=True)
    ap.add_argument("--first", type=float, default=10.0)
    ap.add_argument("--bracket", type=float, nargs=2)
    ap.add_argument("--rel-tol", type=float, default=0.1)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--lo", type=float, default=0.01)
    ap.add_argument("--hi", type=float, default=100.0)
    a = ap.parse_args()
    code = "pysph-" + a.scheme
    seeds = " ".join(str(s) for s in range(1, a.seeds + 1))
    probes = []
    settled = []

    def trial(c):
        """Run (or reuse) the seeds at c; the pooled trial."""
        name = c0_name(c)
        env = dict(os.environ, OUT=a.out, RES="%g" % a.re, C0S=name, SEEDS=seeds,
                   SCHEMES=a.scheme, TABLE="0")
        subprocess.run(["bash", os.path.join(HERE, "pysph_c0.sh")], env=env, check=True)
        runs = [r for r in table.load(a.out) if r["seed"] <= a.seeds]
        p = table.pooled(runs, code, a.re, float(name))
        shear = table.pooled(runs, "shearsph", a.re, float(name))
        stationary = all(r["stationary"] for r in shear["runs"])
        compressed = p["cls"] in ("over-compressed", "failed")
        probes.append(dict(c0=float(name), eps_stat=p["eps"], linf_stat=p["linf"], cls=p["cls"],
                           seeds=[r["seed"] for r in p["runs"]],
                           eps_per_seed=[r["eps_stat"] for r in p["runs"]],
                           disordered=p["disordered"], stationary=stationary))
        print("probe %-8s pooled eps_stat %.4g (bound %.4g), linf %.3g: %s" % (
            name, p["eps"], p["bound"], p["linf"], p["cls"]), flush=True)
        if p["disordered"] and stationary and not p["failed"]:
            settled.append((float(name), p["eps"]))
        return compressed, p

    def next_probe(l, h, eps0, bound):
        mid = math.sqrt(l * h)
        pts = [(math.log(c), math.log(e - eps0)) for c, e in settled if e - eps0 > 0]
        pts.sort(key=lambda q: abs(q[0] - math.log(mid)))
        if len(pts) < 2:
            return mid
        (x1, y1), (x2, y2) = pts[0], pts[1]
        if x1 == x2:
            return mid
        slope = (y2 - y1) / (x2 - x1)
        if not (slope < 0 and math.isfinite(slope) and bound - eps0 > 0):
            return mid
        c = math.exp(x1 + (math.log(bound - eps0) - y1) / slope)
        if not math.isfinite(c):
            return mid
        t, margin = 1 + a.rel_tol, 1 + 1e-9
        if h / l <= t * t:
            # Where either class closes the bracket.
            lo_c, hi_c = h / t * margin, l * t / margin
        else:
            # A factor 1 + rel_tol from each end.
            lo_c, hi_c = l * t / margin, h / t * margin
        if lo_c > hi_c:
            return mid
        return min(max(c, lo_c), hi_c)

    factor = math.sqrt(10.0)
    lo = hi = None  # (c0, pooled)
    if a.bracket:
        for c in a.bracket:
            comp, p = trial(c)
            if comp:
                lo = (c, p) if lo is None or c > lo[0] else lo
            else:
                hi = (c, p) if hi is None or c < hi[0] else hi
        if lo is None or hi is None or lo[0] > hi[0]:
            sys.exit("pysph_c0_bisect: --bracket %g %g does not bracket the bound" % tuple(a.bracket))
    else:
        c = min(max(a.first, a.lo), a.hi)
        comp, p = trial(c)
        if comp:
            lo = (c, p)
            while c * factor <= a.hi * (1 + 1e-12):
                c *= factor
                comp, p = trial(c)
                if comp:
                    lo = (c, p)
                else:
                    hi = (c, p)
                    break
        else:
            hi = (c, p)
            while c / factor >= a.lo * (1 - 1e-12):
                c /= factor
                comp, p = trial(c)
                if comp:
                    lo = (c, p)
                    break
                hi = (c, p)
    if lo and hi:
        for _ in range(64):
            if hi[0] / lo[0] <= 1 + a.rel_tol:
                break
            c = next_probe(lo[0], hi[0], hi[1]["eps0"], hi[1]["bound"])
            c = float(c0_name(c))
            comp, p = trial(c)
            if comp:
                lo = (c, p)
            else:
                hi = (c, p)
    res = dict(scheme=a.scheme, re=a.re, rel_tol=a.rel_tol, seeds=a.seeds, bracket_start=a.bracket,
               first=None if a.bracket else a.first,
               c0_compaction=hi[0] if hi else None, class_there=hi[1]["cls"] if hi else None,
               linf_there=hi[1]["linf"] if hi else None,
               compressed_below=lo[0] if lo else None,
               c0_min_ok=hi[0] if hi and hi[1]["cls"] == "ok" else None, probes=probes)
    with open(os.path.join(a.out, "bisect-%s-re%g.json" % (a.scheme, a.re)), "w") as fh:
        json.dump(res, fh, indent=1)
    if hi:
        print("%s, Re = %g: eps_stat <= eps0 + 0.01 from %s U (over-compressed at %s U); there %s "
              "(linf %.3g U): %s" % (
                  code, a.re, c0_name(hi[0]), c0_name(lo[0]) if lo else "-", hi[1]["cls"],
                  hi[1]["linf"], "c0_min = %s U" % c0_name(hi[0]) if hi[1]["cls"] == "ok"
                  else "no c0 ok at the compaction bound"))
    else:
        print("%s, Re = %g: over-compressed up to %g U" % (code, a.re, a.hi))


if __name__ == "__main__":
    main()
