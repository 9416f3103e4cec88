#!/bin/bash
# Where the step of the SPHinXsys-matched scene (`bench --sphinxsys-match
# --tau 1 --columns 120`, 2760 particles, 1228 steps) goes, pass by pass:
# REPS runs of BIN on THREADS threads, each pass's microseconds a step
# (kernel pass, density sums, force pass, the list's rebuilds, and the
# rest: kick-drift, the rebuild rule's check, the time step), the least
# and the median of the runs. BIN needs the JSON's kernel_s, sums_s and
# forces_s (this folder's build and later).
# usage: passes.sh BIN THREADS REPS [env...]
BIN=$1; T=$2; R=$3; shift 3
for i in $(seq $R); do env "$@" $BIN bench --sphinxsys-match --threads $T --tau 1 --columns 120 2>/dev/null; done | python3 -c "
import json,sys
rows=[json.loads(l) for l in sys.stdin if l.strip()]
for d in rows: d['rest_s']=d['wall_s']-d['kernel_s']-d['sums_s']-d['forces_s']-d['rebuild_s']
def us(d,k): return d[k]*1e6/d['steps']
keys=['wall_s','kernel_s','sums_s','forces_s','rebuild_s','rest_s']
mins={k:min(us(d,k) for d in rows) for k in keys}
meds={k:sorted(us(d,k) for d in rows)[len(rows)//2] for k in keys}
print('T=$T', ' '.join('%s %.1f/%.1f'%(k[:-2],mins[k],meds[k]) for k in keys), '(min/median us per step)')
"
