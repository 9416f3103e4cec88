#!/usr/bin/env bash
# The pair loops' machine code through llvm-mca: for every AVX-512 instance
# of the three pair passes (kernel, density sums, forces; one instance per
# kernel, or per combination of the force pass's constants:
# `forces_chunk_on::<SYMMETRIC, AV, MIRROR>`, the pressure form, the
# artificial viscosity, the walls' factor), each innermost vectorised loop:
# its instructions, llvm-mca's cycles an iteration and the resource it
# finds busiest. A static model of the core (`-mcpu`, default
# sapphirerapids), not a timing: it shows which loops were vectorised and
# what bounds them, where the machine's noise hides a few per cent
# (bench/peers/README.md quotes these figures).
#
# usage: scripts/mca-pair-loops.sh [MCPU]
#
# Builds the release binary with v0 symbol mangling (so that each instance
# is named with its kernel or constants) into target/mca, then reads it
# with objdump. Needs llvm-mca and llvm-cxxfilt (Debian: `llvm`) and
# objdump (`binutils`). x86-64 only.
set -euo pipefail
MCPU=${1:-sapphirerapids}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
for tool in llvm-mca llvm-cxxfilt objdump python3; do
    if ! command -v "$tool" >/dev/null; then
        echo "error: $tool not found: install the Debian package llvm (llvm-mca, llvm-cxxfilt), binutils (objdump) or python3" >&2
        exit 2
    fi
done
if [ "$(uname -m)" != x86_64 ]; then
    echo "error: the pair loops' AVX-512 instances exist on x86-64 only (this is $(uname -m))" >&2
    exit 2
fi
echo "building the release binary with v0 symbol names into target/mca" >&2
(cd "$ROOT" && RUSTFLAGS="-Csymbol-mangling-version=v0" cargo build --release --quiet --target-dir target/mca)
BIN="$ROOT/target/mca/release/shearsph"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
objdump -d --no-show-raw-insn "$BIN" >"$TMP/all.s"
python3 - "$TMP" "$MCPU" <<'EOF'
import re, subprocess, sys

tmp, mcpu = sys.argv[1], sys.argv[2]
want = re.compile(r'(forces_chunk_on|kernel_chunk_on|density_chunk_on)6avx512')
head = re.compile(r'^([0-9a-f]+) <(.*)>:$')
insn = re.compile(r'^\s*([0-9a-f]+):\s*(.*)$')
funcs, cur = [], None
for line in open(f'{tmp}/all.s'):
    line = line.rstrip('\n')
    m = head.match(line)
    if m:
        cur = (m.group(2), []) if want.search(m.group(2)) else None
        if cur:
            funcs.append(cur)
        continue
    m = insn.match(line)
    if cur is not None and m:
        cur[1].append((int(m.group(1), 16), re.sub(r'\s+<[^>]*>', '', m.group(2)).strip()))


def demangle(sym):
    return subprocess.run(['llvm-cxxfilt', sym], capture_output=True, text=True).stdout.strip()


def back_jump(ins):
    """The target of a jump to an earlier address, or None."""
    addr, text = ins
    m = re.match(r'^j[a-z]+\s+([0-9a-f]+)$', text)
    if m and int(m.group(1), 16) < addr:
        return int(m.group(1), 16)
    return None


packed = re.compile(r'^v(add|sub|mul|div|sqrt|min|max|gather\w*)p[sd]\s')
rows = []
for sym, body in funcs:
    name = demangle(sym).replace('shearsph::solver::step::', '').replace('shearsph::kernels::', '')
    for k, ins in enumerate(body):
        target = back_jump(ins)
        if target is None:
            continue
        start = next(i for i, x in enumerate(body) if x[0] >= target)
        loop = body[start:k]
        # innermost: no other jump back inside it
        if any(back_jump(x) is not None for x in loop):
            continue
        text = [t for _, t in loop if not re.match(r'^j[a-z]+\s', t)]
        # vectorised: packed arithmetic, gathers or 512-bit registers
        # (the density sums add in 128-bit lanes)
        if not any('zmm' in t or packed.match(t) for t in text):
            continue
        src = f'{tmp}/loop.s'
        open(src, 'w').write('\n'.join(text) + '\n')
        out = subprocess.run(['llvm-mca', f'-mcpu={mcpu}', '-iterations=300', src],
                             capture_output=True, text=True)
        if out.returncode != 0:
            why = (out.stderr.strip().splitlines() or [f'llvm-mca exited {out.returncode}'])[0]
            rows.append((name, target, len(text), None, why))
            continue
        cycles = int(re.search(r'Total Cycles:\s+(\d+)', out.stdout).group(1)) / 300
        lines = out.stdout.splitlines()
        busiest = ''
        for i, l in enumerate(lines):
            if l.startswith('Resource pressure per iteration:'):
                names = {}
                for r in lines:
                    m = re.match(r'^\[(\d+)\]\s+-\s+(\S+)$', r)
                    if m:
                        names[int(m.group(1))] = m.group(2)
                vals = lines[i + 2].split()
                nums = [(float(v) if v != '-' else 0.0) for v in vals]
                j = max(range(len(nums)), key=lambda q: nums[q])
                busiest = f'{names.get(j, j)} {nums[j]:.1f}'
                break
        rows.append((name, target, len(text), cycles, busiest))

if not rows:
    sys.exit('error: no vectorised loop found in the AVX-512 instances of the pair passes '
             '(were they renamed? the script looks for forces_chunk_on, kernel_chunk_on, '
             'density_chunk_on)')
print(f'llvm-mca -mcpu={mcpu}, 300 iterations of each innermost vectorised loop')
print(f'{"instance":62s} {"loop at":>8s} {"instr":>5s} {"cycles/iter":>11s}  busiest resource (cycles/iter)')
for name, target, n, cycles, busiest in rows:
    c = f'{cycles:11.2f}' if cycles is not None else f'{"-":>11s}'
    print(f'{name:62s} {target:8x} {n:5d} {c}  {busiest}')
EOF
