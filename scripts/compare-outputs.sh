#!/usr/bin/env bash
# Compare the outputs of this tree's `shearsph` with those of OLD_REV, byte
# for byte, to show that a change which moves code keeps the numbers.
#
#   scripts/compare-outputs.sh OLD_REV            # e.g. main, b6a1c99
#   OLD_BIN=/path/to/shearsph scripts/compare-outputs.sh -   # an old binary already built
#
# OLD_REV is checked out in a temporary git worktree and built there with its
# own target dir (COMPARE_TARGET_DIR, default target/compare-old, kept between
# runs so a second comparison is quick); this tree is built with
# `cargo build --release`. Both binaries then run the same set:
#   - `run` of the default scene of every kernel (`shearsph kernels --json`),
#   - one scene per pressure form (paper, symmetric) and wall model (zero,
#     mirrored), and the AV-off and Tait-EOS paths,
#   - `c0 --json` for every kernel, `kernels --json`,
# and every file written (summary.json, profile.csv, timeseries.csv,
# scene.toml, the SVG charts, the JSON on stdout, stderr and the exit status
# of each run: the default scene of `morris` has no positive derived root and
# must fail the same way) is compared with cmp.
#   - a small `sweep` (its results.jsonl rows, sorted, each in the flat
#     layout rows had before issue 12 made a row its key plus the run's
#     summary: see row.jq below; `dt_limit` read as `dt_limit_dominant`),
# summary.json and `run --json` gained c0_over_u, dt_limit_dominant,
# particle_steps and failure_kind (the fields a sweep row had and a summary
# lacked, issue 12): they are dropped before the comparison, so the fields
# both write are compared.
# Ignored, because they are wall-clock measurements and differ between any
# two runs of the same binary: the fields `wall_s` and `particle_steps_per_s`
# of summary.json and of `run --json`, and `wall_s` of the sweep's rows (set
# to 0 before the comparison). The run's charts are compared too (they hold
# only simulated numbers); the sweep's are not (its speed chart plots wall
# time).
# Exit status 0 when everything matches, 1 otherwise (the differing files
# are listed with a diff of their first lines).
set -euo pipefail

old_rev=${1:?usage: scripts/compare-outputs.sh OLD_REV  (or - with OLD_BIN set)}
root=$(git rev-parse --show-toplevel)
cd "$root"
work=$(mktemp -d "${TMPDIR:-/tmp}/compare-outputs.XXXXXX")
cleanup() {
    if [[ -n "${old_tree:-}" ]]; then git worktree remove --force "$old_tree" >/dev/null 2>&1 || true; fi
    rm -rf "$work"
}
trap cleanup EXIT
[[ -n "${KEEP:-}" ]] && trap - EXIT && echo "keeping $work" >&2

if [[ "$old_rev" == "-" ]]; then
    old_bin=${OLD_BIN:?OLD_BIN must name the old binary when OLD_REV is -}
else
    old_tree="$work/old-tree"
    git worktree add --detach "$old_tree" "$old_rev" >/dev/null
    target=${COMPARE_TARGET_DIR:-$root/target/compare-old}
    echo "building $old_rev in $old_tree (target $target)" >&2
    (cd "$old_tree" && CARGO_TARGET_DIR="$target" cargo build --release --quiet --bin shearsph)
    old_bin="$target/release/shearsph"
    cp "$old_bin" "$work/shearsph-old"
    old_bin="$work/shearsph-old"
fi
echo "building this tree" >&2
cargo build --release --quiet --bin shearsph
new_bin="$root/target/release/shearsph"

# The set: one line per run, a name and the flags.
scenes() {
    "$new_bin" kernels --json | jq -r '.[].kernel' | while read -r k; do
        echo "default-$k --kernel $k"
        echo "rule10-$k --kernel $k --c0 rule10"
    done
    echo "symmetric --kernel monaghan --pressure-form symmetric"
    echo "paper-mirrored --kernel morris --c0 rule10 --pressure-form paper --wall-velocity mirrored"
    echo "symmetric-mirrored --kernel monaghan --pressure-form symmetric --wall-velocity mirrored"
    echo "zero-walls --kernel composite --wall-velocity zero --n 8"
    echo "no-av --kernel monaghan --alpha 0"
    echo "tait-negative --kernel monaghan --gamma 7 --allow-negative-pressure"
    echo "steady-jitter --kernel morris --c0 2*rule10 --initial steady --jitter 0.01 --n 8"
}

# A sweep row in the layout of the rows before issue 12 (a flat row of its
# own fields), whatever the layout it was written in: since issue 12 a row is
# its point's key and the run's summary flattened, with summary.json's names
# (n_layers, linf_rel_err, l2_rel_err, linf_rel_err_max), an absolute rms_v
# (the old row's was relative to U) and failure_reason without the
# " (t = ...)" the old row appended (failure_t holds it). The new axes'
# fields (lattice, h_over_d, jitter, seed) are kept only when not the
# defaults every old row had; the summary's other fields are not compared.
cat >"$work/row.jq" <<'JQ'
(if has("outcome") then
    with_entries(.key |= ({"n_layers": "n", "linf_rel_err": "linf", "l2_rel_err": "l2",
                           "linf_rel_err_max": "linf_max"}[.] // .))
    | .rms_v = (if .rms_v == null or .u == null then null else .rms_v / .u end)
 else with_entries(if .key == "dt_limit" then .key = "dt_limit_dominant" else . end) end)
| .new_axes = ([.lattice // "triangular", .h_over_d // "1", .jitter // 0, .seed // 0]
               | if . == ["triangular", "1", 0, 0] then null else . end)
| .failure_reason |= (if . == null then . else sub(" \\(t = [-0-9.e+]+\\)$"; "") end)
| .wall_s = 0
| {index, id, kernel, n, re, alpha, c0_spec, c0_rule, c0, c0_over_u, class, failure_kind,
   failure_reason, linf, linf_max, l2, max_eps, eps_bound, rms_v, steps, dt_limit_dominant, dt,
   particles, particle_steps, t_end, t, wall_s, new_axes}
JQ

produce() { # BIN DIR
    local bin=$1 dir=$2
    mkdir -p "$dir"
    "$bin" kernels --json >"$dir/kernels.json"
    "$bin" kernels --json | jq -r '.[].kernel' | while read -r k; do
        "$bin" c0 --kernel "$k" --json >"$dir/c0-$k.json"
        "$bin" c0 --kernel "$k" --n 16 --re 100 --alpha 0.1 --json >"$dir/c0-$k-n16.json"
    done
    # A small sweep (every outcome class, the no-c0 row of morris's derived
    # rule): its rows, in grid order, wall time zeroed. `dt_limit` is read as
    # `dt_limit_dominant`, its name since the two limits were told apart.
    "$bin" sweep --kernel monaghan,morris,composite --n 8 --re 1,30 --c0 derived,rule10,table2 \
        --c0-over-u 0.02,1 --t-end 20 --jobs 2 --quiet --no-charts --out "$dir/sweep" \
        >/dev/null 2>"$dir/sweep.stderr" || echo "exit $?" >"$dir/sweep.status"
    jq -c -S -f "$work/row.jq" "$dir/sweep/results.jsonl" | sort -t: -k2 >"$dir/sweep-rows.jsonl"
    rm -rf "$dir/sweep"
    scenes | while read -r name flags; do
        # shellcheck disable=SC2086
        "$bin" run $flags --quiet --json --out "$dir/$name" >"$dir/$name.stdout.json" 2>"$dir/$name.stderr" \
            || echo "exit $?" >"$dir/$name.status"
        for f in "$dir/$name/summary.json" "$dir/$name.stdout.json"; do
            if [[ -s "$f" ]]; then
                jq -S '.wall_s = 0 | .particle_steps_per_s = 0
                    | del(.c0_over_u, .dt_limit_dominant, .particle_steps, .failure_kind)' "$f" >"$f.norm" \
                    && mv "$f.norm" "$f"
            fi
        done
    done
}

echo "running the set with $old_bin" >&2
produce "$old_bin" "$work/old"
echo "running the set with $new_bin" >&2
produce "$new_bin" "$work/new"

status=0
count=0
while IFS= read -r -d '' f; do
    rel=${f#"$work/old/"}
    # Counted as the new tree's are (a list of a run folder's own files is
    # compared, not counted).
    [[ $(basename "$f") == .shearsph-files ]] || count=$((count + 1))
    if ! cmp -s "$f" "$work/new/$rel"; then
        echo "DIFFERS: $rel" >&2
        diff <(head -c 4000 "$f") <(head -c 4000 "$work/new/$rel") | head -20 >&2 || true
        status=1
    fi
done < <(find "$work/old" -type f -print0 | sort -z)
# A file only the new binary wrote is a difference too (but for the run
# folder's list of its own files, .shearsph-files, which only a tree with
# the staged output set writes: bookkeeping, no number).
new_count=$(find "$work/new" -type f ! -name .shearsph-files | wc -l)
if [[ "$new_count" -ne "$count" ]]; then
    echo "DIFFERS: old wrote $count files, new $new_count" >&2
    status=1
fi
if [[ $status -eq 0 ]]; then
    echo "identical: $count files (wall_s, particle_steps_per_s zeroed)"
fi
exit $status
