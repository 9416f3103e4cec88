"""The table of bench/peers/pysph_c0.sh: per Re and c0 rung, each code's
eps_stat and linf_stat per seed and pooled (the seeds' mean, as shearsph
pools them), its class by shearsph's rules (over-compressed: eps_stat >
eps0 + 0.01, eps0 the lattice's pulsation from shearsph's eps_bound;
inaccurate: linf_stat > 0.05 U; else ok), the time to disorder (first frame
with dy_rms >= 0.1 d); then each code's law eps_stat - eps0 = k (U/c0)^m
fitted by least squares on ln-ln over its disordered rungs whose excess is at
least 1e-3 and at least eps0 (shearsph's rule, docs/stationary.md), the c0
that law gives for the tolerance 0.01, and the ratio of the two codes'.

usage: python3 pysph_c0_table.py OUT   (prints the table; writes OUT/runs.jsonl)
"""
import glob
import json
import math
import os
import re
import sys
from statistics import mean


def fit(points):
    """Least squares ln(excess) = ln k + m ln(U/c0); (k, m) or None."""
    if len(points) < 2:
        return None
    xs = [math.log(1.0 / c) for c, _ in points]
    ys = [math.log(e) for _, e in points]
    xm, ym = mean(xs), mean(ys)
    sxx = sum((x - xm) ** 2 for x in xs)
    if sxx == 0:
        return None
    m = sum((x - xm) * (y - ym) for x, y in zip(xs, ys)) / sxx
    return math.exp(ym - m * xm), m


def main():
    out = sys.argv[1]
    runs = []
    for path in sorted(glob.glob(os.path.join(out, "shearsph-re*-c*-s*.json"))):
        tag = re.search(r"shearsph-(re.*)\.json$", path).group(1)
        peer = os.path.join(out, "pysph-%s.json" % tag)
        if not os.path.exists(peer) or os.path.getsize(peer) == 0:
            continue
        s = json.load(open(path))
        p = json.load(open(peer))
        eps0 = s["eps_bound"] - s["eps_margin"] if "eps_margin" in s else s["eps_bound"] - 0.01
        for code, r in (("shearsph", s), ("pysph", p)):
            runs.append(dict(
                code=code, re=s["re"], c0=s["c0_over_u"], seed=p["seed"], eps0=eps0,
                eps_bound=s["eps_bound"], t_end=r.get("t", r.get("window_to")),
                window_from=r["window_from"], window_to=r.get("window_to", r.get("t")),
                eps_stat=r["eps_stat"], eps_max_mean=r["eps_max_mean"],
                linf_stat=r["linf_stat"], dy_rms=r["dy_rms"], t_disorder=r["t_disorder"],
                stationary=r.get("stationary"), wall_s=r["wall_s"], steps=r["steps"],
                failed=(r.get("outcome", "ok") != "ok") or not r.get("finite", True)))
    with open(os.path.join(out, "runs.jsonl"), "w") as fh:
        for r in runs:
            fh.write(json.dumps(r) + "\n")

    def cls(eps, linf, bound, failed):
        if failed:
            return "failed"
        if eps > bound:
            return "over-compressed"
        if linf > 0.05:
            return "inaccurate"
        return "ok"

    for re_ in sorted({r["re"] for r in runs}):
        print("Re = %g, N = 10, Monaghan, square lattice h = d, alpha 0.1, jitter 0.05 d" % re_)
        print("%-7s %-9s %-26s %-8s %-8s %-16s %-18s %s" % (
            "c0/U", "code", "eps_stat per seed", "pooled", "linf", "class", "t_disorder/seed", "window per seed"))
        laws = {}
        for code in ("shearsph", "pysph"):
            laws[code] = []
        for c0 in sorted({r["c0"] for r in runs if r["re"] == re_}):
            for code in ("shearsph", "pysph"):
                rs = sorted((r for r in runs if r["re"] == re_ and r["c0"] == c0 and r["code"] == code),
                            key=lambda r: r["seed"])
                if not rs:
                    continue
                e = mean(r["eps_stat"] for r in rs)
                lf = mean(r["linf_stat"] for r in rs)
                c = cls(e, lf, rs[0]["eps_bound"], any(r["failed"] for r in rs))
                td = "/".join("%.1f" % r["t_disorder"] if r["t_disorder"] is not None else "-" for r in rs)
                win = " ".join("(%g, %g]" % (r["window_from"], r["window_to"]) for r in rs)
                print("%-7g %-9s %-26s %-8.4g %-8.3g %-16s %-18s %s" % (
                    c0, code, " ".join("%.4g" % r["eps_stat"] for r in rs), e, lf, c, td, win))
                eps0 = rs[0]["eps0"]
                disordered = all(r["dy_rms"] >= 0.1 for r in rs)
                if disordered and not any(r["failed"] for r in rs) and e - eps0 >= max(1e-3, eps0):
                    laws[code].append((c0, e - eps0))
        c0law = {}
        for code in ("shearsph", "pysph"):
            f = fit(laws[code])
            if f:
                k, m = f
                c0law[code] = (k / 0.01) ** (1.0 / m)
                print("law %-8s eps_stat - eps0 = %.3g (U/c0)^%.3g over c0/U = %s; c0 for delta 0.01: %.3g U" % (
                    code, k, m, ",".join("%g" % c for c, _ in laws[code]), c0law[code]))
            else:
                print("law %-8s: fewer than two rungs to fit" % code)
        if len(c0law) == 2:
            ratio = c0law["pysph"] / c0law["shearsph"]
            print("c0(delta 0.01) PySPH / shearsph = %.3f: %s within a factor 1.5" % (
                ratio, "agree" if 1 / 1.5 <= ratio <= 1.5 else "do NOT agree"))
        print()


if __name__ == "__main__":
    main()
