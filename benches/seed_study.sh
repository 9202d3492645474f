#!/usr/bin/env bash
# The study benchmark of issue 16 (item 4): `drillopt solve problems/bench/seed_study.toml` in a
# fresh temporary output directory with every core of the machine, then wall time, simulations,
# the optimum, its objective with a confidence interval, and the solve's status.
#
#   benches/seed_study.sh                                   # the benchmark (multi-fidelity: 30 explore points, 32 full samples per candidate)
#   benches/seed_study.sh --samples 5 --budget 16 --threads 1   # a small check of the script
#                  (--samples must exceed the explore's 4; --single-fidelity --samples 2 also works)
#
# Options (all optional):
#   --samples N, --budget N, --threads N   passed to `drillopt solve` (default threads: nproc)
#   --duration S   a copy of the problem with [simulation] duration = S seconds (study commands
#                  have no --duration: the window enters the model hash); NOT the benchmark
#   --problem FILE another problem (default problems/bench/seed_study.toml)
#   --single-fidelity  a copy of the problem without its [optimizer.explore] section (the study at
#                  the full fidelity only: the figure before multi-fidelity)
#   --keep         keep the output directory (printed) instead of deleting it
# DRILLOPT=path/to/drillopt uses that binary; otherwise `cargo build --release` (untimed) and
# target/release/drillopt. Needs python3 (the summary reads solution.json and evaluations.csv).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

problem="$root/problems/bench/seed_study.toml"
threads="$(nproc)"
duration=""
keep=0
single=0
pass=()
while [ $# -gt 0 ]; do
    case "$1" in
        --samples | --budget) pass+=("$1" "$2"); shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        --duration) duration="$2"; shift 2 ;;
        --problem) problem="$(realpath "$2")"; shift 2 ;;
        --keep) keep=1; shift ;;
        --single-fidelity) single=1; shift ;;
        -h | --help) sed -n '2,19p' "$0"; exit 0 ;;
        *) echo "seed_study.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    esac
done
cd "$root"

if [ -z "${DRILLOPT:-}" ]; then
    cargo build --release --quiet
    DRILLOPT="$root/target/release/drillopt"
fi

out="$(mktemp -d "${TMPDIR:-/tmp}/seed_study.XXXXXX")"
if [ "$keep" = 0 ]; then trap 'rm -rf "$out"' EXIT; fi

run_problem="$problem"
if [ -n "$duration" ]; then
    # The same file with the duration of its [simulation] table replaced.
    run_problem="$out/$(basename "$problem")"
    awk -v d="$duration" '
        /^\[/ { section = $0 }
        section == "[simulation]" && /^duration *=/ { print "duration = \"" d " s\"   # seed_study.sh --duration"; next }
        { print }' "$problem" >"$run_problem"
    grep -q 'seed_study.sh --duration' "$run_problem" || { echo "no [simulation] duration in $problem" >&2; exit 2; }
fi

if [ "$single" = 1 ]; then
    # The same file without its [optimizer.explore] tables (up to the next table that is not one).
    cp "$run_problem" "$out/with_explore.toml"
    run_problem="$out/single_fidelity_$(basename "$problem")"
    awk '
        /^\[/ { skip = ($0 ~ /^\[optimizer\.explore(\.basis)?\]/) }
        !skip { print }' "$out/with_explore.toml" >"$run_problem"
    if grep -q '^\[optimizer\.explore' "$run_problem" || cmp -s "$run_problem" "$out/with_explore.toml"; then
        echo "--single-fidelity: no [optimizer.explore] section in $problem" >&2; exit 2
    fi
fi

cmd=("$DRILLOPT" solve "$run_problem" --out "$out/solve" --threads "$threads" ${pass[@]+"${pass[@]}"})
echo "command: ${cmd[*]}"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
start=$(date +%s.%N)
status=0
/usr/bin/time -f "%e %M" -o "$out/time.txt" "${cmd[@]}" >"$out/solve.log" 2>&1 || status=$?
end=$(date +%s.%N)
if [ "$status" != 0 ]; then
    tail -n 30 "$out/solve.log"
    echo "drillopt solve failed (exit status $status); log in $out/solve.log" >&2
    trap - EXIT
    exit "$status"
fi

python3 - "$out/solve" "$start" "$end" "$out/time.txt" "$threads" <<'EOF'
import csv, json, math, random, sys

solve, start, end, timefile = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
threads = int(sys.argv[5])
s = json.load(open(f"{solve}/solution.json"))
rows = list(csv.DictReader(open(f"{solve}/evaluations.csv")))
wall = end - start
peak_mb = int(open(timefile).read().split()[1]) / 1024
w = s["work"]
points = len(s["evaluations"])

# The statistics of src/stats/statistic.rs, for the bootstrap of the score over the samples.
def tail_mean(worst_first, level):
    n = len(worst_first)
    mass = (1 - min(max(level, 0.0), 1.0)) * n
    if abs(mass - round(mass)) <= 1e-9:
        mass = round(mass)
    if mass <= 0:
        return worst_first[0]
    whole = math.floor(mass)
    total = sum(worst_first[:whole]) + (mass - whole) * (worst_first[whole] if whole < n else 0)
    return total / mass

def statistic(st, v):
    kind, level = st["kind"], st.get("level")
    if kind == "mean":
        return sum(v) / len(v)
    if kind == "cvar":
        return tail_mean(sorted(v, reverse=True), level)
    if kind == "lower_cvar":
        return tail_mean(sorted(v), level)
    if kind == "max":
        return max(v)
    if kind == "min":
        return min(v)
    if kind == "std_dev":
        m = sum(v) / len(v)
        return math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    raise KeyError(kind)

def score(obj, samples):
    value = statistic(obj["statistic"], [x[obj["quantity"]] for x in samples])
    for r in obj["risk"]:
        value -= r["weight"] * statistic(r["statistic"], [x[r["metric"]] for x in samples])
    return value

print(f"wall time:   {wall:.1f} s (solve's own: {w['wall_time_s']:.1f} s; peak memory {peak_mb:.0f} MB; {w['executor']})")
by = w.get("by_fidelity") or {}
if by:  # multi-fidelity: rows per fidelity (the last column of evaluations.csv)
    parts = []
    for f in ("explore", "full"):
        n = sum(1 for r in rows if r["fidelity"] == f)
        k = len({(r["omega [rpm]"], r["v0 [m/h]"]) for r in rows if r["fidelity"] == f})
        parts.append(f"{f} {n} = {k} points × {by[f]['samples_per_point']} samples")
    shape = "; ".join(parts)
else:
    shape = f"{points} points × {w['samples_per_point']} samples"
print(f"simulations: {len(rows)} rows of evaluations.csv ({shape}) "
      f"({w['simulations_run']} run, {w['simulations_from_cache']} from the cache, {w['simulations_failed']} failed), "
      f"{wall / max(w['simulations_run'], 1):.2f} s of wall time per simulation run "
      f"(with the numerical check at the optimum; × threads: {wall * threads / max(w['simulations_run'], 1):.2f} core·s)")
try:  # each simulation's own wall time, recorded in the evaluation cache, per fidelity (model hash)
    cached = [json.loads(l) for l in open(f"{solve}/cache.jsonl") if l.strip()]
    groups = {}
    for r in cached:
        groups.setdefault(r["key"]["model_hash"], []).append(r["info"]["wall_time_s"])
    # Fidelities by their run counts (evaluations.csv), else "model A", "model B" in cache order.
    counts = {f: sum(1 for r in rows if r.get("fidelity") == f) for f in ("explore", "full")}
    for i, times in enumerate(groups.values()):
        times.sort()
        name = next((f for f, n in counts.items() if n == len(times)), f"model {chr(65 + i)}")
        print(f"one simulation ({name}): mean {sum(times) / len(times):.2f} s, median {times[len(times) // 2]:.2f} s, "
              f"range {times[0]:.2f}–{times[-1]:.2f} s over {len(times)} (cache.jsonl)")
except (OSError, KeyError, ValueError, ZeroDivisionError) as e:
    print(f"one simulation: unknown ({e})")
print(f"status:      {s['status']} ({s['termination']}), method {s['method']}")
o = s.get("optimum")
if o is None:
    print("optimum:     none (no feasible point)")
    sys.exit(0)
obj = s["objective"]
print(f"optimum:     Ω = {o['omega_rpm']:.2f} rpm, V0 = {o['v0_m_per_h']:.3f} m/h")
terms = " ".join(f"− {r['weight']:g}·{r['statistic']['kind']}{('_' + format(r['statistic']['level'], 'g')) if 'level' in r['statistic'] else ''}({r['metric']}) = {r['penalty']:.3f}"
                 for r in obj["risk"])
print(f"objective:   {obj['score']:.4f} {obj['quantity_unit']} = {obj['statistic']['kind']}({obj['quantity']}) {obj['quantity_value']:.3f} {terms}")
ci = {k: v for k, v in obj.items() if "confidence" in k or "interval" in k}
if ci:
    lo, hi = obj.get("score_interval", [float("nan")] * 2)
    print(f"  {100 * obj.get('score_confidence', float('nan')):g} % interval of solution.json (its own bootstrap, src/study/score.rs): "
          f"[{lo:.4f}, {hi:.4f}] {obj['quantity_unit']}")
samples = [x["metrics"] for x in s["metrics_per_sample"] if "metrics" in x]
try:
    again = score(obj, samples)
    if abs(again - obj["score"]) > 1e-9 * max(1.0, abs(obj["score"])):
        raise ValueError(f"recomputed score {again} differs from the report's")
    rng = random.Random(0)
    boot = sorted(score(obj, [rng.choice(samples) for _ in samples]) for _ in range(2000))
    print(f"  95 % bootstrap interval over its {len(samples)} samples (percentile, 2000 resamples; "
          f"the script's own): [{boot[49]:.4f}, {boot[1949]:.4f}] {obj['quantity_unit']}")
except (KeyError, ValueError, IndexError) as e:
    print(f"  no bootstrap interval: {e}")
for c in (s.get("constraints") or {}).get("chance", []):
    print(f"  chance: P({c['metric']} > {c['threshold']:g}) = {c['probability']:.3f} "
          f"(≤ {c['max_probability']:g}: {'satisfied' if c['satisfied'] else 'VIOLATED'})")
nc = s.get("numerical_check")
if nc:
    basis = lambda b: " ".join(f"{k} {v}" for k, v in b.items()) if isinstance(b, dict) else str(b)
    print(f"  numerical check at the optimum (basis {basis(nc['basis'])} → {basis(nc['refined_basis'])}): "
          f"{'converged' if nc['converged'] else 'NOT converged'} on the metrics the problem uses")
    for name, m in sorted(nc.get("metrics", {}).items()):
        if m.get("used") or not m.get("converged", True):
            print(f"    {name}: {m['value']:.6g} → {m['refined_basis']:.6g} ({100 * (m['refined_basis'] - m['value']) / abs(m['value']):+.2f} %, limit "
                  f"{100 * m['limit']:g} %){'' if m.get('used') else ', not used'}"
                  f"{'' if m.get('converged', True) else ', NOT converged'}")
EOF
if [ "$keep" = 1 ]; then echo "results in $out"; fi
