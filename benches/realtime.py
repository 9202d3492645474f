#!/usr/bin/env python3
"""The simulator's real-time factor: simulated seconds per CPU second of `drillopt simulate`, on
one core, for the seed paper's 90 s run and 10 s of each field well; optionally beside a baseline
binary, run in turn (A B A B ...) so that the ratio, not the machine's speed, is the figure.

    benches/realtime.py                      # target/release/drillopt (cargo build --release first, untimed)
    benches/realtime.py --quick              # the seed over 10 s instead of 90 s (a check of the script)
    DRILLOPT=new BASELINE=old benches/realtime.py --repeat 3
                                             # both binaries, 3 runs each per case, median ratios
    benches/realtime.py --study              # also the study benchmark (benches/seed_study.sh), wall time

Options:
  --quick        the seed over 10 s, the wells over 2 s
  --repeat N     runs per case and binary (default 1); the medians are printed
  --cases a,b    only these cases (names in the table: seed, well_a_1km, well_a_3km, well_1km, lateral_200m)
  --study        also run benches/seed_study.sh (every core; several minutes) with DRILLOPT and, when given,
                 BASELINE, and print both wall times

Each run is `RAYON_NUM_THREADS=1 taskset -c 0 drillopt simulate FILE --duration S --quiet --out TMP`
(taskset when it exists); its CPU time (user + system) is the operating system's accounting of the
finished child. The real-time factor is S / CPU s (1: as fast as the string moves; > 1 faster).
The table also gives the steps, the rejected share of step attempts and the Newton iterations per
step from the run's summary.json, and ROP / SSI as a check that both binaries ran the same problem.
Needs python3 only.
"""
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (name, problem file, simulated seconds, quick seconds)
CASES = [
    ("seed", "problems/seed_mc2014.toml", 90.0, 10.0),
    ("well_a_1km", "problems/field/well_a_1km.toml", 10.0, 2.0),
    ("well_a_3km", "problems/field/well_a_3km.toml", 10.0, 2.0),
    ("well_1km", "problems/field/well_1km.toml", 10.0, 2.0),
    ("lateral_200m", "problems/field/lateral_200m.toml", 10.0, 2.0),
]


def usage(message):
    print(f"realtime.py: {message} (see --help)", file=sys.stderr)
    sys.exit(2)


def parse(argv):
    opts = {"quick": False, "repeat": 1, "cases": None, "study": False}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        elif a == "--quick":
            opts["quick"] = True
        elif a == "--study":
            opts["study"] = True
        elif a in ("--repeat", "--cases"):
            if i + 1 >= len(argv):
                usage(f"{a} needs a value")
            value = argv[i + 1]
            i += 1
            if a == "--repeat":
                if not value.isdigit() or int(value) < 1:
                    usage(f"--repeat takes a whole number ≥ 1, got '{value}'")
                opts["repeat"] = int(value)
            else:
                names = value.split(",")
                known = {c[0] for c in CASES}
                for n in names:
                    if n not in known:
                        usage(f"unknown case '{n}' (known: {', '.join(sorted(known))})")
                opts["cases"] = names
        else:
            usage(f"unknown option {a}")
        i += 1
    return opts


def binary(variable):
    path = os.environ.get(variable)
    if path is None:
        return None
    if not os.access(path, os.X_OK):
        usage(f"{variable}={path} is not an executable file")
    return os.path.abspath(path)


def run_once(exe, problem, seconds):
    """One simulate; (cpu s, summary dict)."""
    out = tempfile.mkdtemp(prefix="realtime.")
    try:
        cmd = [exe, "simulate", os.path.join(ROOT, problem), "--duration", f"{seconds:g}",
               "--quiet", "--out", os.path.join(out, "run")]
        if shutil.which("taskset"):
            cmd = ["taskset", "-c", "0"] + cmd
        env = dict(os.environ, RAYON_NUM_THREADS="1")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        done = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        summary_path = os.path.join(out, "run", "summary.json")
        if done.returncode != 0 or not os.path.exists(summary_path):
            sys.exit(f"realtime.py: {' '.join(cmd)} failed (exit {done.returncode}):\n{done.stderr[-2000:]}")
        with open(summary_path) as f:
            return cpu, json.load(f)
    finally:
        shutil.rmtree(out, ignore_errors=True)


def describe(summary):
    s, m = summary["solver"], summary.get("metrics") or {}
    attempts = s["steps"] + s["rejected_steps"]
    return {
        "steps": s["steps"],
        "rejected": s["rejected_steps"] / max(attempts, 1),
        "newton": s["newton_iterations"] / max(s["steps"], 1),
        "rop": m.get("mean_rop_m_per_h", float("nan")),
        "ssi": m.get("stick_slip_severity", float("nan")),
        "status": summary.get("status"),
    }


def main():
    opts = parse(sys.argv[1:])
    exe = binary("DRILLOPT")
    if exe is None:
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
        exe = os.path.join(ROOT, "target", "release", "drillopt")
    base = binary("BASELINE")
    rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    print(f"binary A: {exe}" + (f"\nbinary B (baseline): {base}" if base else ""))
    print(f"machine: {os.cpu_count()} cores, load average {' '.join(open('/proc/loadavg').read().split()[:3])}; "
          f"checkout {rev.stdout.strip() or '?'}; {opts['repeat']} run(s) per case and binary, medians")
    header = f"{'case':<13} {'sim s':>6} {'CPU s':>8} {'RTF':>7} {'steps':>8} {'rej %':>6} {'Newton/step':>11} {'ROP m/h':>8} {'SSI':>6}"
    if base:
        header += f" | {'B CPU s':>8} {'B RTF':>7} {'B steps':>8} {'A/B CPU':>8}"
    print(header)
    for name, problem, seconds, quick in CASES:
        if opts["cases"] and name not in opts["cases"]:
            continue
        if opts["quick"]:
            seconds = quick
        a_cpu, b_cpu, ratios = [], [], []
        for _ in range(opts["repeat"]):
            cpu, summary = run_once(exe, problem, seconds)
            a_cpu.append(cpu)
            a = describe(summary)
            if base:
                cpu_b, summary_b = run_once(base, problem, seconds)
                b_cpu.append(cpu_b)
                b = describe(summary_b)
                ratios.append(cpu / cpu_b)
        cpu = statistics.median(a_cpu)
        line = (f"{name:<13} {seconds:>6g} {cpu:>8.2f} {seconds / cpu:>7.2f} {a['steps']:>8} "
                f"{100 * a['rejected']:>6.1f} {a['newton']:>11.2f} {a['rop']:>8.3f} {a['ssi']:>6.3f}")
        if base:
            cb = statistics.median(b_cpu)
            line += f" | {cb:>8.2f} {seconds / cb:>7.2f} {b['steps']:>8} {statistics.median(ratios):>8.3f}"
        print(line, flush=True)
    if opts["study"]:
        for label, binary_path in (("A", exe), ("B", base)):
            if binary_path is None:
                continue
            start = time.monotonic()
            done = subprocess.run([os.path.join(ROOT, "benches", "seed_study.sh")], cwd=ROOT,
                                  env=dict(os.environ, DRILLOPT=binary_path), capture_output=True, text=True)
            wall = time.monotonic() - start
            if done.returncode != 0:
                sys.exit(f"realtime.py: seed_study.sh with {binary_path} failed:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
            optimum = next((l for l in done.stdout.splitlines() if l.startswith("optimum:")), "optimum: ?")
            print(f"study benchmark ({label}): {wall:.1f} s wall on {os.cpu_count()} cores; {optimum}")


if __name__ == "__main__":
    main()
