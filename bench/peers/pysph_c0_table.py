"""The tables of bench/peers/pysph_c0.sh, from the runs in OUT.

Per Re: the ladder of the jittered starts (seeds >= 1): per c0 and code
(shearsph; PySPH by scheme: pysph-matched, pysph-tvf and any variant),
eps_stat and linf_stat per seed and pooled (the seeds' mean, as shearsph
pools them), the class by shearsph's rules (over-compressed: eps_stat >
eps0 + 0.01, eps0 the kernel's lattice pulsation on the square lattice at
h = d (`shearsph kernels`: Monaghan 8.6183e-4 for shearsph, the matched
scheme and TVF with the cubic spline; the quintic, `morris`, 6.3225e-5 for
TVF's stock kernel); inaccurate: linf_stat > 0.05 U; else ok), the time to
disorder (first frame with dy_rms >= 0.1 d) and the window; then the perfect
lattice (seed 0) the same way; then each code's law eps_stat - eps0 =
k (U/c0)^m fitted by least squares on ln-ln over its pooled, disordered c0s
whose excess is at least 1e-3 and at least eps0 (shearsph's rule,
docs/stationary.md), and the c0 that law gives for the tolerance 0.01.

usage: python3 pysph_c0_table.py OUT   (prints the tables; writes OUT/runs.jsonl)
"""
import glob
import json
import math
import os
import re
import sys
from statistics import mean

EPS0 = {"monaghan": 8.6183e-4, "quintic": 6.3225e-5}
MARGIN = 0.01
LINF_BOUND = 0.05


def kernel_of(code):
    return "quintic" if code in ("pysph-tvf", "pysph-tvf_pb0", "pysph-tvf_walls") else "monaghan"


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


def load(out):
    """Every run as a dict; PySPH's judged on the window of shearsph's run of
    the same scene and seed."""
    runs = []
    for path in sorted(glob.glob(os.path.join(out, "shearsph-re*-c*-s*.json"))):
        m = re.search(r"shearsph-re([0-9.]+)-c([0-9.]+)-s([0-9]+)\.json$", path)
        if not m or os.path.getsize(path) == 0:
            continue
        s = json.load(open(path))
        tag = "re%s-c%s-s%s" % m.groups()
        seed = int(m.group(3))
        pairs = [("shearsph", s)]
        for peer in sorted(glob.glob(os.path.join(out, "pysph-*-%s.json" % tag))):
            scheme = re.match(r"pysph-(.*)-%s\.json$" % re.escape(tag), os.path.basename(peer)).group(1)
            if os.path.getsize(peer) == 0:
                continue
            pairs.append(("pysph-" + scheme, json.load(open(peer))))
        for code, r in pairs:
            eps0 = EPS0[kernel_of(code)]
            runs.append(dict(
                code=code, re=s["re"], c0=s["c0_over_u"], seed=seed, eps0=eps0,
                eps_bound=eps0 + MARGIN, t_end=r.get("t", r.get("window_to")),
                window_from=r["window_from"], window_to=r.get("window_to", r.get("t")),
                eps_stat=r["eps_stat"], eps_max_mean=r["eps_max_mean"],
                linf_stat=r["linf_stat"], dy_rms=r["dy_rms"], t_disorder=r["t_disorder"],
                stationary=r.get("stationary"), wall_s=r["wall_s"], steps=r["steps"],
                dt=r.get("dt"), n_fluid=r.get("n_fluid", r.get("fluid_particles")),
                failed=(r.get("outcome", "ok") != "ok") or not r.get("finite", True)))
    return runs


def classify(eps, linf, bound, failed):
    if failed:
        return "failed"
    if eps > bound:
        return "over-compressed"
    if linf > LINF_BOUND:
        return "inaccurate"
    return "ok"


def pooled(runs, code, re_, c0, perfect=False, seeds=None):
    """The runs of one code, Re and c0 (seeds >= 1 pooled, or the perfect
    lattice; only `seeds` if given), with the pooled eps_stat, linf_stat and
    class; None if none."""
    rs = sorted((r for r in runs if r["code"] == code and r["re"] == re_ and r["c0"] == c0
                 and (r["seed"] == 0) == perfect and (seeds is None or r["seed"] in seeds)),
                key=lambda r: r["seed"])
    if not rs:
        return None
    e = mean(r["eps_stat"] for r in rs)
    lf = mean(r["linf_stat"] for r in rs)
    failed = any(r["failed"] for r in rs)
    return dict(runs=rs, eps=e, linf=lf, cls=classify(e, lf, rs[0]["eps_bound"], failed),
                failed=failed, disordered=all(r["dy_rms"] >= 0.1 for r in rs),
                eps0=rs[0]["eps0"], bound=rs[0]["eps_bound"])


CODES = ["shearsph", "pysph-matched", "pysph-tvf", "pysph-tvf_pb0", "pysph-tvf_cubic",
         "pysph-tvf_walls"]


def law(runs, code, re_, only=None):
    """(k, m, c0s) of the code's disordered law at Re (over the c0s in
    `only` if given), or None."""
    pts = []
    for c0 in sorted({r["c0"] for r in runs if r["re"] == re_}):
        if only is not None and c0 not in only:
            continue
        p = pooled(runs, code, re_, c0)
        if p and p["disordered"] and not p["failed"] and p["eps"] - p["eps0"] >= max(1e-3, p["eps0"]):
            pts.append((c0, p["eps"] - p["eps0"]))
    f = fit(pts)
    return (f[0], f[1], [c for c, _ in pts]) if f else None


def main():
    out = sys.argv[1]
    runs = load(out)
    with open(os.path.join(out, "runs.jsonl"), "w") as fh:
        for r in runs:
            fh.write(json.dumps(r) + "\n")
    codes = [c for c in CODES if any(r["code"] == c for r in runs)]
    for re_ in sorted({r["re"] for r in runs}):
        c0s = sorted({r["c0"] for r in runs if r["re"] == re_})
        print("Re = %g, N = 10, square lattice h = d; jittered starts (0.05 d), seeds pooled" % re_)
        print("%-8s %-16s %-30s %-9s %-7s %-16s %-20s %s" % (
            "c0/U", "code", "eps_stat per seed", "pooled", "linf", "class", "t_disorder/seed",
            "window per seed"))
        for c0 in c0s:
            for code in codes:
                p = pooled(runs, code, re_, c0)
                if not p:
                    continue
                rs = p["runs"]
                td = "/".join("%.1f" % r["t_disorder"] if r["t_disorder"] is not None else "-"
                              for r in rs)
                win = " ".join("(%g, %g]" % (r["window_from"], r["window_to"]) for r in rs)
                print("%-8g %-16s %-30s %-9.4g %-7.3g %-16s %-20s %s" % (
                    c0, code, " ".join("%.4g" % r["eps_stat"] for r in rs), p["eps"], p["linf"],
                    p["cls"], td, win))
        if any(r["seed"] == 0 and r["re"] == re_ for r in runs):
            print("the perfect lattice (seed 0, no jitter)")
            print("%-8s %-16s %-10s %-8s %-16s %-10s %s" % (
                "c0/U", "code", "eps_stat", "linf", "class", "dy_rms end", "window"))
            for c0 in c0s:
                for code in codes:
                    p = pooled(runs, code, re_, c0, perfect=True)
                    if not p:
                        continue
                    r = p["runs"][0]
                    print("%-8g %-16s %-10.4g %-8.3g %-16s %-10.3g (%g, %g]" % (
                        c0, code, p["eps"], p["linf"], p["cls"], r["dy_rms"], r["window_from"],
                        r["window_to"]))
        for code in [c for c in codes if c in ("shearsph", "pysph-matched", "pysph-tvf")]:
            f = law(runs, code, re_)
            if f:
                k, m, cs = f
                print("law %-15s eps_stat - eps0 = %.3g (U/c0)^%.3g over c0/U = %s; c0 for delta 0.01: %.3g U"
                      % (code, k, m, ",".join("%.4g" % c for c in cs), (k / 0.01) ** (1.0 / m)))
            else:
                print("law %-15s not fitted (fewer than two disordered c0s with excess >= max(1e-3, eps0))"
                      % code)
        print()


if __name__ == "__main__":
    main()
