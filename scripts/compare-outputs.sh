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
#   - a small `sweep` (its results.jsonl rows, sorted, `dt_limit` read as
#     `dt_limit_dominant`, the row field's name since issue 12),
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
    jq -c -S 'with_entries(if .key == "dt_limit" then .key = "dt_limit_dominant" else . end)
        | .wall_s = 0' "$dir/sweep/results.jsonl" | sort -t: -k2 >"$dir/sweep-rows.jsonl"
    rm -rf "$dir/sweep"
    scenes | while read -r name flags; do
        # shellcheck disable=SC2086
        "$bin" run $flags --quiet --json --out "$dir/$name" >"$dir/$name.stdout.json" 2>"$dir/$name.stderr" \
            || echo "exit $?" >"$dir/$name.status"
        for f in "$dir/$name/summary.json" "$dir/$name.stdout.json"; do
            if [[ -s "$f" ]]; then
                jq -S '.wall_s = 0 | .particle_steps_per_s = 0' "$f" >"$f.norm" && mv "$f.norm" "$f"
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
    count=$((count + 1))
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
