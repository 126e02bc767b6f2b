#!/bin/bash
# FE subgrade benchmark: quasi-static solves of a layered subgrade block of ~1M dofs on 1 and 2
# MPI processes, and re-solves with the reused AMG preconditioner at ~100k dofs. Writes the
# "FE subgrade" section of docs/benchmarks.md (other sections are left as they are).
#
#   cases/bench/fem/run.sh [BUILD_DIR]      (default: build-fem; builds trackbed_fem_bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${1:-$root/build-fem}
cmake --build "$build" -j2 --target trackbed_fem_bench > /dev/null
bench=$(find "$build" -name trackbed_fem_bench -type f -executable | head -1)
mpirun=(mpirun --allow-run-as-root --oversubscribe --bind-to none)
results=$(mktemp)
run() { "${mpirun[@]}" -np "$1" "$bench" "$2" "$3" "$4" "$5" | tee -a "$results"; }
#   processes dofs degree re-solves tolerance
run 1 1e6 1 3 1e-8
run 2 1e6 1 3 1e-8
run 1 1e5 1 10 1e-8
run 2 1e5 1 10 1e-8
run 1 1e5 2 10 1e-8
run 1 1e5 1 10 1e-6

python3 - "$results" "$root/docs/benchmarks.md" <<'PY'
import datetime, re, subprocess, sys
rows = [dict(kv.split("=") for kv in line.split()) for line in open(sys.argv[1]) if "=" in line]
cpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
model = re.search(r"Model name:\s*(.+)", cpu).group(1).strip()
cores = re.search(r"^CPU\(s\):\s*(\d+)", cpu, re.M).group(1)
load = open("/proc/loadavg").read().split()[0]
lines = [
    "## FE subgrade",
    "",
    f"Quasi-static solve of a layered subgrade block (8 m x 4 m x 4 m: sub-ballast, fill, ground;",
    f"fixed base, roller sides, gravity and a 100 kN sleeper-footprint load), CG + ML AMG with the",
    f"rigid-body modes, relative tolerance 1e-8 unless stated. Setup = dofs, sparsity and stiffness assembly;",
    f"AMG = preconditioner setup; re-solve = load change (2 % more, slightly lateral) + load",
    f"assembly + CG from the previous solution with the AMG reused (mean of several).",
    f"Produced by `cases/bench/fem/run.sh` on {datetime.date.today()}, {model}, {cores} CPUs",
    f"(`lscpu`), load average {load} at the end (another build may have shared the machine).",
    "",
    "| processes | degree | tolerance | dofs | setup s | AMG s | first solve s (its.) | re-solve s (its.) | of which CG s |",
    "|---|---|---|---|---|---|---|---|---|",
]
for r in rows:
    lines.append(f"| {r['processes']} | Q{r['degree']} | {r['tolerance']} | {int(r['dofs']):,} | {r['setup_s']} | {r['amg_s']} | "
                 f"{r['first_solve_s']} ({r['first_iterations']}) | {r['resolve_s']} ({r['resolve_iterations']}) | "
                 f"{r['resolve_solve_s']} |")
def resolve(tolerance):
    return [r["resolve_s"] for r in rows if r["processes"] == "1" and r["degree"] == "1"
            and int(r["dofs"]) < 500000 and r["tolerance"] == tolerance]
if resolve("1e-08"):
    lines += ["", "Goal (issue 5): a re-solve with the reused preconditioner well under 1 s for the ~100k-dof",
              f"subgrade of a single-sleeper section. Measured here (Q1, 1 process): {resolve('1e-08')[0]} s at",
              f"tolerance 1e-8, {(resolve('1e-06') or ['-'])[0]} s at 1e-6. The CG iterations dominate (load assembly",
              "is a few per cent). Timings taken while other builds ran on the same 2 cores are inflated,",
              "most for 2 processes."]
section = "\n".join(lines) + "\n"
path = sys.argv[2]
try:
    text = open(path).read()
except FileNotFoundError:
    text = "# Benchmarks\n"
pattern = re.compile(r"^## FE subgrade\n.*?(?=^## |\Z)", re.S | re.M)
if pattern.search(text):
    text = pattern.sub(lambda m: section + "\n", text).rstrip("\n") + "\n"
else:
    text = text.rstrip("\n") + "\n\n" + section
open(path + ".tmp", "w").write(text)
import os; os.replace(path + ".tmp", path)
PY
rm -f "$results"
echo "wrote the FE subgrade section of $root/docs/benchmarks.md"
