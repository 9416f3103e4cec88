"""The ladder chart of a peer comparison: wall time against L_inf error, one
line per code and thread count, from the CSV peer_summary.py writes
(--csv). Needs matplotlib: pysph_setup.sh installs it into the PySPH venv.

usage: peer_chart.py LADDER.csv OUT.png [TITLE] [FOOTNOTE]
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {"shearsph": ("tab:blue", "o"), "pysph": ("tab:orange", "s"), "sphinxsys": ("tab:green", "^")}


def main():
    src, out = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "Poiseuille start-up, laddered over resolution"
    groups = {}
    with open(src) as f:
        for r in csv.DictReader(f):
            groups.setdefault((r["code"], int(r["threads"])), []).append(
                (float(r["wall_s"]), float(r["linf_rel_err"]), float(r["half_width"])))
    fig, ax = plt.subplots(figsize=(7, 5))
    for (code, thr), pts in sorted(groups.items()):
        pts.sort(key=lambda p: p[2])  # joined in order of resolution
        color, marker = STYLE.get(code, ("black", "x"))
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color=color, marker=marker,
                linestyle="-" if thr == 1 else "--", label=f"{code}, {thr} thread{'s' if thr > 1 else ''}")
        for w, e, hw in pts:
            ax.annotate(f"{hw:g}", (w, e), textcoords="offset points", xytext=(3, 3), fontsize=7, color=color)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time of the steps, s")
    ax.set_ylabel("L_inf error of the layer-mean velocity / U")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    foot = "labels: particles across the half-width B"
    if len(sys.argv) > 4:
        foot += "; " + sys.argv[4]
    fig.text(0.01, 0.01, foot, fontsize=7)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)
    print(f"chart written to {out}")


if __name__ == "__main__":
    main()
