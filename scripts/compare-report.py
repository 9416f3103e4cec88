#!/usr/bin/env python3
"""Compare two `shearsph report` folders file by file, the wall-clock
measurements aside: the CSV columns wall_s, wall_s_at and pareto_wall (the
Pareto front over wall time), `wall_s` and `particle_steps_per_s` of
runs.jsonl, and "<number> s" in the
sentences of verdicts.json and index.html. speed_accuracy.svg (it plots wall
time) is left out, in the page too. Every other file must be byte for byte the same.

    scripts/compare-report.py OLD_DIR NEW_DIR [FILE ...]

With FILEs, only those are compared (e.g. the CSVs and JSON, when the page
changed on purpose). Exit 0 when all match, 1 otherwise (each difference
listed)."""
import csv, io, json, os, re, sys

WALL_COLUMNS = {"wall_s", "wall_s_at", "pareto_wall"}
SECONDS = re.compile(r"-?[0-9][0-9.]*(e[+-]?[0-9]+)? s\b")
SKIP = {"speed_accuracy.svg"}


def normal(name, data):
    if name.endswith(".csv"):
        rows = list(csv.reader(io.StringIO(data.decode())))
        if rows:
            drop = [i for i, h in enumerate(rows[0]) if h in WALL_COLUMNS]
            for r in rows[1:]:
                for i in drop:
                    if i < len(r):
                        r[i] = "#"
        out = io.StringIO()
        csv.writer(out, lineterminator="\n").writerows(rows)
        return out.getvalue().encode()
    if name.endswith(".jsonl"):
        lines = []
        for line in data.decode().splitlines():
            v = json.loads(line)
            for key in ("wall_s", "particle_steps_per_s"):
                if key in v:
                    v[key] = 0
            lines.append(json.dumps(v, sort_keys=True))
        return "\n".join(lines).encode()
    if name.endswith(".json") or name.endswith(".html"):
        text = data.decode()
        # the inline speed chart over wall time
        text = re.sub(r'<figure id="fig-speed_accuracy">.*?</figure>', "", text, flags=re.S)
        text = SECONDS.sub("# s", text)
        # the c0 table's wall-seconds column (the last cell of its rows)
        text = re.sub(r"<td>[^<]*</td></tr>", "<td>#</td></tr>", text)
        return text.encode()
    return data


def main():
    old, new, *only = sys.argv[1:]
    names = only or sorted(set(os.listdir(old)) | set(os.listdir(new)))
    bad = 0
    for name in names:
        if name in SKIP:
            continue
        a, b = os.path.join(old, name), os.path.join(new, name)
        if not (os.path.isfile(a) and os.path.isfile(b)):
            print(f"only in one: {name}")
            bad += 1
            continue
        if normal(name, open(a, "rb").read()) != normal(name, open(b, "rb").read()):
            print(f"differs: {name}")
            bad += 1
        else:
            print(f"same: {name}")
    print(f"{len([n for n in names if n not in SKIP]) - bad} same, {bad} different")
    sys.exit(1 if bad else 0)


main()
