#!/usr/bin/env python3
"""Robustness (fuzz) campaign for the `drillopt` CLI.

Deterministic from --seed: file i is mutated with random.Random(f"{seed}:file:{i}") and its
command is fixed by the plan, so the same seed, count and problem set give the same files and
command lines on any binary.

    python3 campaign.py --binary PATH --seed S --count N --out DIR [--problems DIR] [--jobs J]
                        [--cli 200] [--repro-dir DIR] [--keep-all]

Writes DIR/results.jsonl (one record per run), DIR/files/*.toml (the mutated file of every
non-OK run; all with --keep-all), DIR/summary.json (counts per command and class, the findings),
DIR/findings.md, and minimal reproducers under --repro-dir (default DIR/repro).
"""
import argparse
import copy
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import threading
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor

# ----------------------------------------------------------------------------------------------
# TOML writer
# ----------------------------------------------------------------------------------------------
BARE = re.compile(r"^[A-Za-z0-9_-]+$")


class Raw:
    """A value written verbatim (e.g. a 20-digit integer that TOML cannot hold)."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return f"Raw({self.text})"

    def __deepcopy__(self, memo):
        return Raw(self.text)


def fmt_key(k):
    return k if BARE.match(k) else json.dumps(k, ensure_ascii=False)


def fmt_val(v):
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(fmt_val(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{fmt_key(k)} = {fmt_val(x)}" for k, x in v.items()) + "}"
    return json.dumps(str(v))


def is_aot(v):
    return isinstance(v, list) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def dump_toml(doc, dup=()):
    """doc -> TOML text. `dup`: dotted table paths whose header and body are written twice."""
    out = []

    def emit_table(d, path, header, aot=False):
        body = []
        for k, v in d.items():
            if isinstance(v, dict) or is_aot(v):
                continue
            body.append(f"{fmt_key(k)} = {fmt_val(v)}")
        if header is not None:
            hp = ".".join(fmt_key(p) for p in path)
            hdr = f"[[{hp}]]" if aot else f"[{hp}]"
            times = 2 if (".".join(path) in dup and not aot) else 1
            for _ in range(times):
                out.append("")
                out.append(hdr)
                out.extend(body)
        else:
            out.extend(body)
        for k, v in d.items():
            if isinstance(v, dict):
                emit_table(v, path + [k], True)
            elif is_aot(v):
                for el in v:
                    emit_table(el, path + [k], True, aot=True)

    emit_table(doc, [], None)
    return "\n".join(out).lstrip("\n") + "\n"


# ----------------------------------------------------------------------------------------------
# Paths in a document
# ----------------------------------------------------------------------------------------------
def path_str(path):
    s = ""
    for p in path:
        if isinstance(p, int):
            s += f"[{p}]"
        else:
            s += ("." if s else "") + p
    return s


def key_str(path):
    """The key a message should name: the path without a trailing index into a value array."""
    p = list(path)
    while p and isinstance(p[-1], int):
        p.pop()
    return path_str(p)


def get_at(doc, path):
    cur = doc
    for p in path:
        cur = cur[p]
    return cur


def set_at(doc, path, value):
    get_at(doc, path[:-1])[path[-1]] = value


def walk(doc, path=()):
    """Yield (path, value) for every node below doc (tables, arrays, leaves)."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield path + (k,), v
            yield from walk(v, path + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield path + (i,), v
            yield from walk(v, path + (i,))


NUM_IN_STR = re.compile(r"^(\s*)([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(\s*)(.*)$")


def leaf_kind(v):
    if isinstance(v, bool):
        return "bool"
    if isinstance(v, (int, float)):
        return "num"
    if isinstance(v, str):
        return "unitstr" if (NUM_IN_STR.match(v) and len(v) < 40) else "str"
    return None


# ----------------------------------------------------------------------------------------------
# Mutations: each is a data record {"op", "path", ...} applied by apply_op (replayable)
# ----------------------------------------------------------------------------------------------
SPECIAL = ["0", "-1", "5e-324", "1e-300", "1e-12", "1e12", "1e300", "x1e3", "x1e-3",
           "nan", "inf", "-inf", "NaN", "99999999999999999999"]
WRONG_UNITS = ["rpm", "m/h", "kN", "MPa", "GPa", "kg/m^3", "mm", "m", "s", "ms", "Hz", "N/m",
               "N/m^3", "1/s", "kg m^2", "s/m", "kN·m", "hp", "lb/ft", "ppg", "m/s^2", "us",
               "rad/s", "ft/h", "psi", "klbf", "%", "K", "J", "m/s", "in"]
UNKNOWN_KEYS = ["bogus", "unknown_key", "Length", "outer_radius_", "xyzzy", "omega2", "law_"]
# the ends of the documented admissible ranges (docs/user-guide.md), a valid but extreme input
EDGES = {
    "model.length": ["1 m", "15 km"],
    "model.gravity": [0, "0.1 m/s^2", "30 m/s^2"],
    "model.pipe.poisson_ratio": [-0.9, 0.499],
    "model.pipe.stiffness_damping": ["0 s", "1 ms"],
    "model.pipe.shear_factor": [0.1, 1],
    "model.pipe.torsion_factor": [0.1, 1],
    "model.pipe.yield_strength": ["10 MPa", "3 GPa"],
    "model.pipe.density": ["1000 kg/m^3", "25000 kg/m^3"],
    "model.fluid.density": ["1000 kg/m^3", "25000 kg/m^3"],
    "model.fluid.annulus_density": [0, "3000 kg/m^3"],
    "model.bit.inertia": [0, "1000 kg m^2"],
    "model.bit.blades": [1, 16],
    "model.wall.slip_smoothing": ["1e-7 m/s", "1e-2 m/s"],
    "model.wall.restitution": [0, 1],
    "mesh.elements": [1, 6, 2000],
    "mesh.basis.bending": [1, "1e6 Hz"],
    "mesh.basis.torsional": [1, "1e6 Hz"],
    "mesh.basis.axial": [1, "1e6 Hz"],
    "operating_point.omega": ["1 rpm", "1000 rpm"],
    "operating_point.v0": [0, "0.1 m/h", "1000 m/h"],
    "operating_point.wob": ["100 N", "2 MN"],
    "operating_point.wob_limit": ["100 N", "2 MN"],
    "operating_point.torque_limit": ["10 N·m", "500 kN·m"],
    "operating_point.power_limit": ["100 W", "10 MW"],
    "operating_point.autodriller_time_constant": ["10 ms", "10 min"],
    "campbell.excitation_multiple": [1, 50],
    "simulation.time_step": ["1 us", "1 s"],
    "simulation.sample_interval": ["1 us", "1 s"],
    "simulation.settling_time": [0],
    "model.pipe.fatigue.stress_concentration": [1, 20],
    "model.pipe.fatigue.endurance_limit": [0, "2000 MPa"],
    "model.pipe.fatigue.log_a1": [5, 40],
    "model.pipe.fatigue.m1": [1, 30],
    "uncertain.samples": [1, 10000],
    "uncertain.parameter.cov": [1e-6, 1],
    "optimizer.max_evaluations": [3, 100000],
    "model.section.length": ["1 mm", "15 km"],
    "model.section.elements": [1, 2000],
}
READS = {
    "modes": ("model", "mesh"),
    "campbell": ("model", "mesh", "operating_point", "campbell"),
    "simulate": ("model", "mesh", "operating_point", "simulation"),
    "verify": ("model", "mesh", "operating_point", "simulation"),
    "compare": ("model", "mesh", "operating_point", "simulation", "uncertain", "objective",
                "constraints"),
    "solve": ("model", "mesh", "operating_point", "simulation", "uncertain", "objective",
              "constraints", "optimizer"),
}


def fmt_number(x, like_int=False):
    if like_int and isinstance(x, (int,)) :
        return str(x)
    r = repr(float(x))
    return r


def special_value(rng, old, in_string):
    """One special replacement for number `old`; returns text (in_string) or a TOML value."""
    choice = rng.choice(SPECIAL + (["2000", "2001", "2"] if isinstance(old, int) else []))
    if choice == "x1e3":
        v = old * 1000
        v = int(v) if isinstance(old, int) else float(v)
    elif choice == "x1e-3":
        v = old / 1000 if not isinstance(old, int) else old / 1000
        v = float(v)
    else:
        v = choice
    if in_string:
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return choice, (str(v) if isinstance(v, int) else repr(v))
        return choice, v
    # a bare value
    if isinstance(v, (int, float)):
        return choice, v
    if v in ("nan", "NaN"):
        return choice, (float("nan") if rng.random() < 0.5 else "nan")
    if v in ("inf", "-inf"):
        return choice, (float(v) if rng.random() < 0.5 else v)
    if v == "99999999999999999999":
        return choice, Raw(v)
    if v == "5e-324":
        return choice, 5e-324
    return choice, (int(v) if re.fullmatch(r"-?\d+", v) and isinstance(old, int) else float(v))


def misspell(rng, unit):
    ops = ["swap", "drop", "double", "upper", "plural", "space", "garbage", "lookalike", "case1"]
    op = rng.choice(ops)
    u = unit
    if op == "swap" and len(u) >= 2:
        i = rng.randrange(len(u) - 1)
        u = u[:i] + u[i + 1] + u[i] + u[i + 2:]
    elif op == "drop" and len(u) >= 2:
        i = rng.randrange(len(u))
        u = u[:i] + u[i + 1:]
    elif op == "double":
        i = rng.randrange(len(u))
        u = u[:i] + u[i] + u[i:]
    elif op == "upper":
        u = u.upper()
    elif op == "plural":
        u = u + "s"
    elif op == "space":
        i = rng.randrange(len(u) + 1)
        u = u[:i] + " " + u[i:]
    elif op == "garbage":
        u = u + rng.choice(["x", "!", "²", "/", "^2", "..", "\t"])
    elif op == "lookalike":
        u = u.replace("m", "ｍ", 1) if "m" in u else u.replace("s", "ѕ", 1) if "s" in u else u + "ı"
    else:
        u = u[:1].upper() + u[1:]
    if u == unit:
        u = unit + "x"
    return op, u


def candidate_paths(doc, command, rng, pred):
    allp = [(p, v) for p, v in walk(doc) if pred(p, v)]
    if not allp:
        return []
    reads = READS.get(command)
    if reads and rng.random() < 0.8:
        sub = [(p, v) for p, v in allp if isinstance(p[0], str) and p[0] in reads]
        if sub:
            return sub
    return allp


def gen_op(doc, rng, command):
    """Draw one mutation for doc (and apply it); returns the op record or None."""
    kinds = ["num", "num", "num", "unit", "unit", "delete", "unknown", "table", "aot",
             "str2num", "bounds", "edge"]
    for _ in range(20):
        kind = rng.choice(kinds)
        if kind == "num":
            c = candidate_paths(doc, command, rng,
                                lambda p, v: leaf_kind(v) in ("num", "unitstr"))
            if not c:
                continue
            p, v = rng.choice(c)
            if leaf_kind(v) == "num":
                choice, new = special_value(rng, v, False)
            else:
                m = NUM_IN_STR.match(v)
                old = float(m.group(2)) if re.search(r"[.eE]", m.group(2)) else int(m.group(2))
                choice, txt = special_value(rng, old, True)
                new = m.group(1) + txt + m.group(3) + m.group(4)
            op = {"op": "num", "path": list(p), "choice": choice, "new": enc(new), "old": enc(v)}
        elif kind == "unit":
            c = candidate_paths(doc, command, rng, lambda p, v: leaf_kind(v) == "unitstr"
                                and NUM_IN_STR.match(v).group(4) != "")
            if not c:
                continue
            p, v = rng.choice(c)
            m = NUM_IN_STR.match(v)
            unit = m.group(4)
            if rng.random() < 0.5:
                nu = rng.choice([u for u in WRONG_UNITS if u != unit])
                how = "wrong_dimension"
            else:
                how, nu = misspell(rng, unit)
                how = "misspelt_" + how
            new = m.group(1) + m.group(2) + (m.group(3) or " ") + nu
            op = {"op": "unit", "path": list(p), "how": how, "new": new, "old": v}
        elif kind == "delete":
            c = candidate_paths(doc, command, rng, lambda p, v: isinstance(p[-1], str))
            if not c:
                continue
            p, v = rng.choice(c)
            op = {"op": "delete", "path": list(p)}
        elif kind == "unknown":
            c = candidate_paths(doc, command, rng, lambda p, v: isinstance(v, dict))
            c = [("root", doc)] + c if rng.random() < 0.1 else c
            if not c:
                continue
            p, v = rng.choice(c)
            p = () if p == "root" else p
            sib = [k for k in v.keys() if len(k) > 3]
            if sib and rng.random() < 0.5:
                k = rng.choice(sib)
                i = rng.randrange(len(k) - 1)
                name = k[:i] + k[i + 1] + k[i] + k[i + 2:]
                if name == k:
                    name = k + "s"
            else:
                name = rng.choice(UNKNOWN_KEYS)
            if name in v:
                name = name + "_x"
            val = rng.choice([1, "1 m", True, 0.5, "x"])
            op = {"op": "unknown", "path": list(p) + [name], "new": enc(val)}
        elif kind == "table":
            c = candidate_paths(doc, command, rng, lambda p, v: isinstance(v, dict))
            if not c:
                continue
            p, v = rng.choice(c)
            in_aot = any(isinstance(x, int) for x in p)
            how = "empty" if (in_aot or rng.random() < 0.5) else "duplicate"
            op = {"op": "table", "path": list(p), "how": how}
        elif kind == "aot":
            c = candidate_paths(doc, command, rng, lambda p, v: is_aot(v))
            if not c:
                continue
            p, v = rng.choice(c)
            how = rng.choice(["reorder", "duplicate", "truncate", "empty", "drop_first"])
            if how == "reorder" and len(v) < 2:
                how = "duplicate"
            perm = list(range(len(v)))
            rng.shuffle(perm)
            if perm == sorted(perm) and len(perm) > 1:
                perm = perm[::-1]
            op = {"op": "aot", "path": list(p), "how": how, "perm": perm,
                  "dup": rng.randrange(len(v))}
        elif kind == "edge":
            c = candidate_paths(doc, command, rng, lambda p, v: norm_key(key_str(p)) in EDGES
                                and not isinstance(v, (dict, list)))
            if not c:
                continue
            p, v = rng.choice(c)
            new = rng.choice(EDGES[norm_key(key_str(p))])
            op = {"op": "edge", "path": list(p), "new": enc(new), "old": enc(v)}
        elif kind == "str2num":
            c = candidate_paths(doc, command, rng, lambda p, v: isinstance(v, str))
            if not c:
                continue
            p, v = rng.choice(c)
            new = rng.choice([0, 60, -1, 1e300, 3.5, Raw("99999999999999999999")])
            op = {"op": "str2num", "path": list(p), "new": enc(new), "old": v}
        else:  # bounds
            c = candidate_paths(doc, command, rng, lambda p, v: isinstance(v, list) and len(v) == 2
                                and not is_aot(v))
            if not c:
                continue
            p, v = rng.choice(c)
            how = "reversed" if rng.random() < 0.8 else "equal"
            op = {"op": "bounds", "path": list(p), "how": how, "old": enc(v)}
        try:
            apply_op(doc, op)
        except Exception:
            continue
        return op
    return None


def enc(v):
    """JSON-safe encoding of a TOML value (for the op record)."""
    if isinstance(v, Raw):
        return {"raw": v.text}
    if isinstance(v, float) and (math.isnan(v) or math.isinf(v)):
        return {"float": repr(v)}
    if isinstance(v, list):
        return [enc(x) for x in v]
    if isinstance(v, dict):
        return {"table": {k: enc(x) for k, x in v.items()}}
    return v


def dec(v):
    if isinstance(v, dict):
        if "raw" in v:
            return Raw(v["raw"])
        if "float" in v:
            return float(v["float"])
        if "table" in v:
            return {k: dec(x) for k, x in v["table"].items()}
    if isinstance(v, list):
        return [dec(x) for x in v]
    return v


def apply_op(doc, op, dup=None):
    p = op["path"]
    o = op["op"]
    if o in ("num", "unit", "str2num", "edge"):
        get_at(doc, p)  # must exist
        set_at(doc, p, dec(op["new"]) if o != "unit" else op["new"])
    elif o == "delete":
        del get_at(doc, p[:-1])[p[-1]]
    elif o == "unknown":
        parent = get_at(doc, p[:-1])
        if not isinstance(parent, dict):
            raise KeyError
        parent[p[-1]] = dec(op["new"])
    elif o == "table":
        t = get_at(doc, p)
        if not isinstance(t, dict):
            raise KeyError
        if op["how"] == "empty":
            t.clear()
        else:
            doc.setdefault("\0dup", set()).add(path_str(p))
    elif o == "aot":
        arr = get_at(doc, p)
        if not is_aot(arr):
            raise KeyError
        how = op["how"]
        if how == "reorder":
            perm = [i for i in op["perm"] if i < len(arr)]
            arr[:] = [arr[i] for i in perm] + arr[len(perm):]
        elif how == "duplicate":
            arr.append(copy.deepcopy(arr[op["dup"] % len(arr)]))
        elif how == "truncate":
            if len(arr) > 1:
                del arr[len(arr) - 1:]
            else:
                set_at(doc, p, [])
        elif how == "drop_first":
            del arr[0]
            if not arr:
                set_at(doc, p, [])
        else:
            set_at(doc, p, [])
    elif o == "bounds":
        arr = get_at(doc, p)
        if op["how"] == "reversed":
            arr.reverse()
        else:
            arr[1] = copy.deepcopy(arr[0])
    else:
        raise ValueError(o)


def render(doc):
    dup = doc.pop("\0dup", set())
    text = dump_toml(doc, dup)
    if dup:
        doc["\0dup"] = dup
    return text


# ----------------------------------------------------------------------------------------------
# Bases: the shipped problems, shortened for the study commands
# ----------------------------------------------------------------------------------------------
SMALL = {"tiny_string", "tiny_multi_fidelity", "slim_pipe_buckling", "slim_pipe_wide_hole",
         "slim_pipe_fatigue", "slim_pipe_hook_load", "slim_pipe_autodriller"}


def load_bases(problems_dir):
    bases = {}
    for root, _, files in os.walk(problems_dir):
        for f in sorted(files):
            if f.endswith(".toml"):
                path = os.path.join(root, f)
                with open(path, "rb") as fh:
                    try:
                        bases[os.path.splitext(f)[0]] = tomllib.load(fh)
                    except Exception:
                        pass
    return dict(sorted(bases.items()))


def shorten(doc, command):
    d = copy.deepcopy(doc)
    sim = d.get("simulation", {})
    sim["duration"] = "0.3 s"
    if "settling_time" in sim:
        sim["settling_time"] = "0.1 s"
    unc = d.get("uncertain")
    if command == "compare":
        d.get("optimizer", {}).pop("explore", None)
    opt = d.get("optimizer", {})
    ex = opt.get("explore")
    if ex is not None:
        ex["duration"] = "0.2 s"
        if "settling_time" in ex:
            ex["settling_time"] = "0.05 s"
    if command == "solve":
        if unc and isinstance(unc.get("samples"), int):
            unc["samples"] = min(unc["samples"], 3)
            unc.pop("sequential", None)
        if "initial_design" in opt:
            opt["initial_design"] = 3
        if ex is not None and "samples" in ex and unc:
            ex["samples"] = min(ex["samples"], max(1, unc.get("samples", 2) - 1))
        if opt.get("method") == "grid":
            opt["grid"] = [2, 2]
    return d


def bases_for(command, bases):
    names = list(bases)
    if command in ("modes", "simulate", "campbell"):
        return names
    if command == "compare":
        unc = [n for n in names if any("parameter" in (bases[n].get("uncertain") or {})
                                        for _ in [0])]
        return unc   # files where --samples 2 is admissible
    return [n for n in names if n in SMALL] or names


# ----------------------------------------------------------------------------------------------
# Runs
# ----------------------------------------------------------------------------------------------
MEM_CAP = 4_000_000_000
TIMEOUT = {"modes": 30, "simulate": 60, "compare": 120, "campbell": 60, "verify": 120,
           "solve": 180, "cli": 120}
MAIN_JSON = {"simulate": "summary.json", "compare": "compare.json", "solve": "solution.json",
             "campbell": "campbell.json", "map": "map.json"}


def command_line(binary, command, fpath, outdir, idx):
    if command == "modes":
        return [binary, "modes", fpath] + (["--json"] if idx % 2 == 0 else [])
    if command == "simulate":
        return [binary, "simulate", fpath, "--duration", "0.05", "--quiet", "--out", outdir]
    if command == "compare":
        return [binary, "compare", fpath, "--point", "60rpm,10m/h", "--samples", "2",
                "--threads", "1", "--quiet", "--out", outdir]
    if command == "campbell":
        return [binary, "campbell", fpath, "--quiet", "--out", outdir]
    if command == "verify":
        return [binary, "verify", fpath, "--duration", "0.1", "--threads", "1", "--quiet"]
    if command == "solve":
        return [binary, "solve", fpath, "--budget", "6", "--threads", "1", "--quiet", "--out",
                outdir]
    raise ValueError(command)


def run(argv, cwd, timeout):
    def pre():
        os.nice(10)
        resource.setrlimit(resource.RLIMIT_AS, (MEM_CAP, MEM_CAP))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    env = dict(os.environ, RAYON_NUM_THREADS="1", NO_COLOR="1")
    env.pop("RUST_BACKTRACE", None)
    so = open(os.path.join(cwd, ".stdout"), "wb+")
    se = open(os.path.join(cwd, ".stderr"), "wb+")
    t0 = time.monotonic()
    p = subprocess.Popen(argv, cwd=cwd, stdout=so, stderr=se, stdin=subprocess.DEVNULL,
                         preexec_fn=pre, env=env, start_new_session=True)
    timed_out = [False]

    def kill():
        timed_out[0] = True
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    timer = threading.Timer(timeout, kill)
    timer.start()
    _, status, ru = os.wait4(p.pid, 0)
    timer.cancel()
    p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - t0
    so.seek(0)
    se.seek(0)
    out = so.read().decode("utf-8", "replace")
    err = se.read().decode("utf-8", "replace")
    so.close()
    se.close()
    return {"rc": p.returncode, "wall": round(wall, 3), "maxrss_kb": ru.ru_maxrss,
            "timeout": timed_out[0], "stdout": out, "stderr": err}


# ----------------------------------------------------------------------------------------------
# Classification
# ----------------------------------------------------------------------------------------------
NUM_TOKEN = re.compile(r"(?<![\w.\-−/])([-−]?)((?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)(?![\w])")
NEG_ZERO = re.compile(r"(?<![\w.])[-−]0(?:\.0*)?(?:[eE][-+]?\d+)?(?![\d.\w])")
NANINF = re.compile(r"(?<![A-Za-z_])(nan|NaN|NAN|inf|Inf|INF|infinity|Infinity)(?![A-Za-z_])")
KEY_RE = re.compile(r"`([A-Za-z_][\w\-]*(?:\[\d+\])?(?:\.[A-Za-z_][\w\-]*(?:\[\d+\])?)*)`"
                    r"|\b([a-z_]+(?:\[\d+\])?(?:\.[a-z_][a-z_0-9]*(?:\[\d+\])?)+)\b"
                    r"|\[\[?([a-z_]+(?:\.[a-z_]+)*)\]\]?")
FLAG_RE = re.compile(r"--[a-z][a-z\-]+")
RANGE_HINT = re.compile(
    r"must|allowed|accept|expected|one of|at most|at least|greater|less than|exceed|between|"
    r"in \[|\[[^\]]*,[^\]]*\]|write |needs|should|instead|e\.g\.|"
    r"possible values|no more than|did you mean|tip:|lie |inside|remove|twice|unique|"
    r"below|above|declare|takes", re.I)
SIG_DIGIT_LIMIT = 15


def sig_digits(num):
    m = re.match(r"(\d*)\.?(\d*)", num.split("e")[0].split("E")[0])
    digits = (m.group(1) + m.group(2)).lstrip("0")
    if "." not in num:
        digits = digits.rstrip("0") if False else digits
    return len(digits)


def terminal_absurd(text, jsonish=False):
    """Reasons why a terminal output of a successful run looks absurd."""
    reasons = []
    if jsonish:
        try:
            obj = json.loads(text)
            for path, v in json_walk(obj):
                if isinstance(v, float) and (math.isnan(v) or math.isinf(v)):
                    reasons.append(f"nan/inf at {path}")
                elif isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) > 1e15:
                    reasons.append(f"magnitude {v:g} > 1e15 at {path}")
                elif isinstance(v, float) and v == 0 and math.copysign(1, v) < 0:
                    reasons.append(f"-0.0 at {path}")
            if re.search(r"-0\.0\b(?![1-9])", text):
                reasons.append("-0.0 in JSON text")
            return reasons[:3]
        except Exception:
            pass
    for m in NANINF.finditer(text):
        ctx = text[max(0, m.start() - 30):m.end() + 10].replace("\n", " ")
        reasons.append(f"nan/inf: …{ctx}…")
        break
    for m in NUM_TOKEN.finditer(text):
        num = m.group(2)
        if sig_digits(num) > SIG_DIGIT_LIMIT:
            reasons.append(f">15 significant digits: {m.group(0)}")
            break
    for m in NUM_TOKEN.finditer(text):
        try:
            if abs(float(m.group(2))) > 1e15:
                ctx = text[max(0, m.start() - 40):m.end() + 10].replace("\n", " ")
                reasons.append(f"magnitude > 1e15: …{ctx}…")
                break
        except ValueError:
            pass
    m = NEG_ZERO.search(text)
    if m:
        ctx = text[max(0, m.start() - 40):m.end() + 10].replace("\n", " ")
        reasons.append(f"negative zero: …{ctx}…")
    return reasons


def json_walk(obj, path="$"):
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k in ("problem_toml",):
                continue
            yield from json_walk(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from json_walk(v, f"{path}[{i}]")
    else:
        yield path, obj


def json_file_absurd(path):
    try:
        with open(path, encoding="utf-8") as fh:
            obj = json.load(fh)
    except Exception as e:  # noqa
        return [f"unreadable {os.path.basename(path)}: {e}"[:200]]
    reasons = []
    for p, v in json_walk(obj):
        if isinstance(v, float) and (math.isnan(v) or math.isinf(v)):
            reasons.append(f"{os.path.basename(path)}: nan/inf at {p}")
        elif isinstance(v, str) and v.strip().lower() in ("nan", "inf", "-inf", "infinity",
                                                            "+inf", "-infinity"):
            reasons.append(f"{os.path.basename(path)}: string {v!r} at {p}")
        if len(reasons) >= 3:
            break
    return reasons


def norm_key(k):
    return re.sub(r"\[\d+\]", "", k)


def keys_in(text):
    keys = set()
    for m in KEY_RE.finditer(text):
        k = m.group(1) or m.group(2) or m.group(3)
        if k and re.search(r"\.(rs|toml|json|md|csv|svg|jsonl)$", k):
            continue
        if k and ("." in k or "[" in k or k in TOP_KEYS):
            keys.add(k)
    return keys


TOP_KEYS = {"model", "mesh", "operating_point", "simulation", "uncertain", "objective",
            "constraints", "optimizer", "expect", "campbell", "name", "description"}


def key_matches(msg_key, mut_key):
    a, b = norm_key(msg_key), norm_key(mut_key)
    if not a or not b:
        return False
    if a == b or a.startswith(b + ".") :
        return True
    if b.startswith(a + ".") and a.count(".") >= 1:
        return True
    if b.startswith(a + ".") and a in TOP_KEYS and b.count(".") <= 1:
        return True
    return False


def error_lines(err, out):
    lines = [l for l in (err + "\n" + out).splitlines() if l.strip()]
    errs = [l for l in lines if not l.lower().startswith("warning")]
    return errs or lines


def classify(rec, mut_keys, fpath, outdir, command, cli=False):
    rc, out, err = rec["rc"], rec["stdout"], rec["stderr"]
    reasons = []
    memcap = "memory allocation of" in err or "out of memory" in err.lower() or \
        "AllocError" in err
    panicked = rc == 101 or "panicked" in err or "RUST_BACKTRACE" in err or "panicked" in out
    if memcap:
        # the 4 GB address-space cap was hit (a Rust abort, or a panic on an AllocError)
        return "UNBOUNDED", "memory_cap" + ("_panic" if panicked else ""), reasons
    if panicked:
        return "PANIC", "panic", reasons
    if rec["timeout"]:
        return "UNBOUNDED", "timeout", reasons
    if rec["maxrss_kb"] > 2_000_000:
        return "UNBOUNDED", "over_2GB", reasons
    verdict = command in ("verify", "cli") and rc == 1 and re.search(r"^verdict:", out, re.M) \
        and "error" not in err.lower()
    if rc == 0 or verdict:
        jsonish = command == "modes" and "--json" in rec["argv"]
        jsonish = jsonish or ("--json" in rec["argv"])
        reasons += terminal_absurd(out, jsonish)
        reasons += ["stderr: " + x for x in terminal_absurd(err, False)]
        if outdir and command in MAIN_JSON:
            mj = os.path.join(outdir, MAIN_JSON[command])
            if not os.path.isfile(mj):
                reasons.append(f"no {MAIN_JSON[command]} in the result folder")
            else:
                reasons += json_file_absurd(mj)
        if rec["maxrss_kb"] > 2_000_000:
            return "UNBOUNDED", "over_2GB", reasons
        return ("EXIT0_ABSURD", "absurd", reasons) if reasons else ("OK_RAN", "ran", reasons)
    # a refusal or failure: how clear is it?
    text = err if err.strip() else out
    elines = error_lines(err, out)
    first = elines[0] if elines else ""
    named = keys_in(text)
    flags = set(FLAG_RE.findall(text))
    names_file = (fpath and (fpath in text or os.path.basename(fpath) in text))
    subs = []
    if not names_file and not named and not flags:
        subs.append("no_location")
    if mut_keys:
        match = any(key_matches(k, mk) for k in named for mk in mut_keys if not mk.startswith("--"))
        # a top-level key (no dot) named in backticks
        match = match or any(f"`{mk}`" in text for mk in mut_keys if "." not in mk)
        for mk in mut_keys:
            # a message on a sibling key that also names the mutated key's leaf (inner_radius vs
            # inner_diameter) locates it too
            parent, _, leaf = norm_key(mk).rpartition(".")
            if parent and len(leaf) >= 3 and re.search(r"\b" + re.escape(leaf) + r"\b", text) and \
                    any(norm_key(k).rpartition(".")[0] == parent for k in named):
                match = True
        first_err = next((l for l in text.splitlines() if l.startswith("error")), first)
        match = match or any(mk in first_err for mk in mut_keys if mk.startswith("--"))
        if not match:
            if cli:
                subs.append("flag_not_named")
            else:
                subs.append("wrong_key" if (named or flags) else "no_key")
    if not RANGE_HINT.search(text):
        subs.append("no_range")
    rec["msg_absurd"] = [m.group(0)[:60] for m in NUM_TOKEN.finditer(text)
                         if sig_digits(m.group(2)) > 17 and m.group(2) not in
                         "99999999999999999999"][:2]
    if subs:
        return "UNCLEAR_ERROR", "+".join(subs), [f"named: {sorted(named)[:6]}",
                                                 f"mutated: {mut_keys}"]
    return "OK_REFUSED", "refused", reasons


# ----------------------------------------------------------------------------------------------
# Signatures (grouping)
# ----------------------------------------------------------------------------------------------
def normalise_line(line, fpath):
    s = line
    if fpath:
        s = s.replace(fpath, "FILE")
    s = re.sub(r"/tmp/\S+", "PATH", s)
    s = re.sub(r"'[^']*'", "'V'", s)
    s = re.sub(r"`[^`]*`", "`K`", s)
    s = re.sub(r"\"[^\"]*\"", "\"V\"", s)
    s = re.sub(r"[-−+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", "N", s)
    s = re.sub(r"\b(?:nan|NaN|inf|Inf)\b", "N", s)
    return s[:170]


def signature(cls, sub, rec, fpath, command):
    err, out = rec["stderr"], rec["stdout"]
    if cls == "PANIC":
        m = re.search(r"panicked at ([^\n]*)\n?([^\n]*)", err)
        loc = re.sub(r":\d+:\d+", "", m.group(1)) if m else "?"
        msg = normalise_line(m.group(2), fpath) if m else normalise_line(err[:150], fpath)
        return f"PANIC at {loc}: {msg}"
    if cls == "UNBOUNDED":
        return f"UNBOUNDED {sub}"
    if cls == "EXIT0_ABSURD":
        r = rec.get("reasons") or ["?"]
        kinds = sorted({re.sub(r"[:(].*", "", x).strip() for x in r})
        return f"ABSURD {command}: " + "; ".join(kinds)
    if cls == "UNCLEAR_ERROR":
        el = error_lines(err, out)
        return f"UNCLEAR {sub}: " + normalise_line(el[0] if el else "", fpath)
    return cls


# ----------------------------------------------------------------------------------------------
# CLI variants on a valid small problem
# ----------------------------------------------------------------------------------------------
def cli_variants(problem, rng):
    Q = ["0", "-1", "5e-324", "1e-300", "1e-12", "1e12", "1e300", "nan", "inf", "-inf", "abc",
         "", " ", "99999999999999999999", "0x10", "١٢٠", "1e", "--", "1,5"]
    V = []
    P = problem
    for q in Q + ["-1s", "1e-7", "2s", "0.5 ms", "1e300s", "NaNs", "infs", "-0", "86401",
                  "5e-324s", "1min1s", "0.05kg", "1e-6"]:
        V.append(("simulate", ["simulate", P, "--duration", q, "--quiet"], "--duration"))
    for q in Q + ["60", "60 rpm", "60RPM", "60rpmm", "-60rpm", "0rpm", "1e300rpm", "1e-300rpm",
                  "5e-324rpm", "1e-12rpm", "1e12rpm", "NaNrpm", "infrpm", "60kN", "1001rpm",
                  "99999999999999999999rpm", "60rpm,5m/h", "6.283185307179586rad/s"]:
        V.append(("simulate", ["simulate", P, "--omega", q, "--duration", "0.05", "--quiet"],
                  "--omega"))
    for q in Q + ["5", "-5m/h", "1e300m/h", "1e-300m/h", "5e-324m/h", "0.05m/h", "1001m/h",
                  "NaNm/h", "infm/h", "5rpm", "5 m / h", "5m/hh", "99999999999999999999m/h",
                  "0m/h", "-0"]:
        V.append(("simulate", ["simulate", P, "--v0", q, "--duration", "0.05", "--quiet"],
                  "--v0"))
    for q in ["1e-300ms", "0", "step", "steps", "-1ms", "1e300s", "nan", "1s", "2s", "abc"]:
        V.append(("simulate", ["simulate", P, "--sample-interval", q, "--duration", "0.05",
                               "--quiet"], "--sample-interval"))
    for q in ["50kN", "0", "nan", "-1kN"]:
        V.append(("simulate", ["simulate", P, "--wob", q, "--duration", "0.05", "--quiet"],
                  "--wob"))
    for q in ["60rpm", "60rpm,", ",10m/h", "60rpm,10m/h,5", "60,10", "1e300rpm,10m/h",
              "60rpm,1e300m/h", "nanrpm,10m/h", "60rpm,nanm/h", "-60rpm,10m/h", "60rpm,-10m/h",
              "0rpm,0m/h", "5e-324rpm,10m/h", "60rpm,5e-324m/h", "", "abc", "60rpm;10m/h",
              "60rpm,10kN", "60 rpm , 10 m/h", "99999999999999999999rpm,10m/h",
              "1e-12rpm,1e-12m/h", "60rpm,0"]:
        V.append(("compare", ["compare", P, "--point", q, "--quiet", "--threads", "1"],
                  "--point"))
    for q in ["0", "-1", "1", "2", "10001", "1e3", "2.0", "abc", "", "99999999999999999999"]:
        V.append(("compare", ["compare", P, "--point", "60rpm,10m/h", "--samples", q,
                              "--quiet", "--threads", "1"], "--samples"))
    for q in ["0", "-1", "1025", "abc", "99999999999999999999", "1.5"]:
        V.append(("compare", ["compare", P, "--point", "60rpm,10m/h", "--threads", q,
                              "--quiet"], "--threads"))
    for q in ["0x0", "1x1", "-3x3", "1e3x2", "abc", "2x", "x2", "3x3x3",
              "99999999999999999999x2", "2.5x2", "201x2", "2x201", "NaNxNaN", "", "2*2", "2X2",
              "2x2"]:
        V.append(("map", ["map", P, "--grid", q, "--quiet", "--threads", "1"], "--grid"))
    for q in ["imperial", "", "FIELD", "Metric", "si", "oilfield", "field ", "1", "nan"]:
        V.append(("modes", ["modes", P, "--units", q], "--units"))
        V.append(("simulate", ["--units", q, "simulate", P, "--duration", "0.05", "--quiet"],
                  "--units"))
    for q in ["0", "-1", "1e3", "99999999999999999999", "100000", "2000", "abc", "1000"]:
        V.append(("modes", ["modes", P, "--count", q], "--count"))
    for q in ["0..0", "200rpm..20rpm", "0rpm..1e300rpm", "nan..inf", "-5rpm..5rpm", "20rpm..",
              "..", "20..200", "1e-300rpm..1rpm", "20rpm..2000rpm", "5e-324rpm..1e-12rpm",
              "20rpm...200rpm", "20rpm-200rpm", "NaNrpm..200rpm", "20rpm..infrpm"]:
        V.append(("campbell", ["campbell", P, "--omega-range", q, "--quiet"], "--omega-range"))
    for q in ["0", "1", "2001", "-1", "99999999999999999999", "abc", "2"]:
        V.append(("campbell", ["campbell", P, "--points", q, "--quiet"], "--points"))
    for q in ["0", "0.5", "51", "nan", "inf", "-1", "1e300", "99999999999999999999", "abc",
              "5e-324"]:
        V.append(("campbell", ["campbell", P, "--multiple", q, "--quiet"], "--multiple"))
    for q in ["0", "2", "3", "100001", "-1", "abc", "1e3", "99999999999999999999"]:
        V.append(("solve", ["solve", P, "--budget", q, "--quiet", "--threads", "1"], "--budget"))
    for q in ["1e-300", "0", "-1", "nan", "1e300", "abc"]:
        V.append(("verify", ["verify", P, "--duration", q, "--quiet", "--threads", "1"],
                  "--duration"))
    for q in ["4m", "0", "1e300m", "nan"]:
        V.append(("simulate", ["simulate", P, "--probe", q, "--duration", "0.05", "--quiet"],
                  "--probe"))
    return V


# ----------------------------------------------------------------------------------------------
# The campaign
# ----------------------------------------------------------------------------------------------
def plan(count, rng, spec=None):
    fixed = {"simulate": 600, "compare": 150, "campbell": 100, "verify": 40, "solve": 40}
    if spec:
        fixed = {k: int(v) for k, v in (x.split("=") for x in spec.split(","))}
    elif count < 10000:
        fixed = {k: max(1, round(v * count / 10000)) for k, v in fixed.items()}
    cmds = []
    for k, v in fixed.items():
        cmds += [k] * v
    cmds += ["modes"] * max(0, count - len(cmds))
    cmds = cmds[:count]
    rng.shuffle(cmds)
    return cmds


def make_file(bases, seed, i, command):
    rng = random.Random(f"{seed}:file:{i}")
    names = bases_for(command, bases)
    base = rng.choice(names)
    doc = bases[base] if command in ("modes", "campbell", "simulate") else shorten(bases[base],
                                                                                    command)
    doc = copy.deepcopy(doc)
    n = rng.choice([1, 1, 1, 2, 2, 3])
    ops = []
    for _ in range(n):
        op = gen_op(doc, rng, command)
        if op:
            ops.append(op)
    return base, doc, ops


def base_doc(bases, base, command):
    return copy.deepcopy(bases[base] if command in ("modes", "campbell", "simulate")
                         else shorten(bases[base], command))


def do_one(args, bases, i, command, keep):
    base, doc, ops = make_file(bases, args.seed, i, command)
    rid = f"f{i:05d}"
    rundir = os.path.join(args.out, "runs", rid)
    os.makedirs(rundir, exist_ok=True)
    fpath = os.path.join(rundir, f"{rid}_{command}.toml")
    with open(fpath, "w", encoding="utf-8") as fh:
        fh.write(render(doc))
    outdir = os.path.join(rundir, "out")
    argv = command_line(args.binary, command, fpath, outdir, i)
    rec = run(argv, rundir, TIMEOUT[command])
    rec["argv"] = argv
    mut_keys = sorted({key_str(op["path"]) for op in ops})
    cls, sub, reasons = classify(rec, mut_keys, fpath, outdir, command)
    rec["reasons"] = reasons
    sig = signature(cls, sub, rec, fpath, command)
    result = {"id": rid, "i": i, "command": command, "base": base, "ops": ops,
              "mut_keys": mut_keys, "kinds": sorted({op["op"] for op in ops}), "class": cls,
              "sub": sub, "sig": sig, "rc": rec["rc"], "wall": rec["wall"],
              "maxrss_kb": rec["maxrss_kb"], "timeout": rec["timeout"], "reasons": reasons,
              "msg_absurd": rec.get("msg_absurd", []), "stderr_head": rec["stderr"][:1500], "stdout_head": rec["stdout"][:800],
              "argv": [a.replace(fpath, "FILE") for a in argv[1:]]}
    if keep or cls not in ("OK_RAN", "OK_REFUSED"):
        os.makedirs(os.path.join(args.out, "files"), exist_ok=True)
        shutil.copy(fpath, os.path.join(args.out, "files", f"{rid}_{command}.toml"))
    shutil.rmtree(rundir, ignore_errors=True)
    return result


def do_cli(args, j, variant, problem):
    command, argv_tail, flag = variant
    rid = f"c{j:04d}"
    rundir = os.path.join(args.out, "runs", rid)
    os.makedirs(rundir, exist_ok=True)
    outdir = os.path.join(rundir, "out")
    argv = [args.binary] + argv_tail
    if command in ("simulate", "compare", "map", "campbell", "solve"):
        argv += ["--out", outdir]
    rec = run(argv, rundir, TIMEOUT["cli"])
    rec["argv"] = argv
    cls, sub, reasons = classify(rec, [flag], problem, outdir if command in MAIN_JSON else None,
                                 command, cli=True)
    rec["reasons"] = reasons
    sig = signature(cls, sub, rec, problem, "cli " + command)
    shutil.rmtree(rundir, ignore_errors=True)
    return {"id": rid, "i": j, "command": "cli", "subcommand": command, "flag": flag,
            "value": argv_tail[argv_tail.index(flag) + 1] if flag in argv_tail else None,
            "base": os.path.basename(problem), "ops": [], "mut_keys": [flag], "kinds": ["cli"],
            "class": cls, "sub": sub, "sig": sig, "rc": rec["rc"], "wall": rec["wall"],
            "maxrss_kb": rec["maxrss_kb"], "timeout": rec["timeout"], "reasons": reasons,
            "msg_absurd": rec.get("msg_absurd", []), "stderr_head": rec["stderr"][:1500], "stdout_head": rec["stdout"][:800],
            "argv": [a.replace(outdir, "OUT") for a in argv[1:]]}


def minimise(args, bases, group):
    """A representative with the fewest mutations; try each of its mutations alone."""
    group = sorted(group, key=lambda r: (len(r["ops"]), r["base"] not in SMALL, r["i"]))
    rep = group[0]
    if rep["command"] == "cli" or len(rep["ops"]) <= 1:
        return rep, None
    for op in rep["ops"]:
        doc = base_doc(bases, rep["base"], rep["command"])
        try:
            apply_op(doc, op)
        except Exception:
            continue
        rid = f"min_{rep['id']}"
        rundir = os.path.join(args.out, "runs", rid)
        os.makedirs(rundir, exist_ok=True)
        fpath = os.path.join(rundir, f"{rid}_{rep['command']}.toml")
        with open(fpath, "w", encoding="utf-8") as fh:
            fh.write(render(doc))
        outdir = os.path.join(rundir, "out")
        argv = command_line(args.binary, rep["command"], fpath, outdir, rep["i"])
        rec = run(argv, rundir, TIMEOUT[rep["command"]])
        rec["argv"] = argv
        mk = [key_str(op["path"])]
        cls, sub, reasons = classify(rec, mk, fpath, outdir, rep["command"])
        rec["reasons"] = reasons
        sig = signature(cls, sub, rec, fpath, rep["command"])
        text = render(doc)
        shutil.rmtree(rundir, ignore_errors=True)
        if cls == rep["class"] and sig.replace(f"min_{rep['id']}", rep["id"]) == rep["sig"] or \
                (cls == rep["class"] and cls in ("PANIC", "UNBOUNDED", "EXIT0_ABSURD")):
            m = dict(rep, ops=[op], mut_keys=mk, kinds=[op["op"]], rc=rec["rc"],
                     stderr_head=rec["stderr"][:1500], stdout_head=rec["stdout"][:800],
                     reasons=reasons, minimised=True, sig=rep["sig"])
            return m, text
    return rep, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", required=True)
    ap.add_argument("--seed", type=int, default=34)
    ap.add_argument("--count", type=int, default=10000)
    ap.add_argument("--out", required=True)
    ap.add_argument("--problems", default=os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "problems"))
    ap.add_argument("--cli-problem", default=None)
    ap.add_argument("--cli", type=int, default=300, help="at most this many command-line variants")
    ap.add_argument("--plan", default=None, help="files per command other than modes, e.g. "
                    "simulate=600,compare=150,campbell=100,verify=40,solve=40 (the default); "
                    "modes gets the rest of --count")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--repro-dir", default=None)
    ap.add_argument("--keep-all", action="store_true")
    ap.add_argument("--only", default=None, help="comma list of commands to run (debug)")
    ap.add_argument("--resume", action="store_true", help="skip ids already in results.jsonl")
    args = ap.parse_args()
    args.binary = os.path.abspath(args.binary)
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    repro_dir = os.path.abspath(args.repro_dir or os.path.join(args.out, "repro"))
    bases = load_bases(args.problems)
    cli_problem = os.path.abspath(args.cli_problem or os.path.join(
        args.problems, "regression", "tiny_string.toml"))
    cmds = plan(args.count, random.Random(f"{args.seed}:plan"), args.plan)
    only = set(args.only.split(",")) if args.only else None
    resf = os.path.join(args.out, "results.jsonl")
    done = {}
    if args.resume and os.path.exists(resf):
        with open(resf) as fh:
            for line in fh:
                r = json.loads(line)
                done[r["id"]] = r
    lock = threading.Lock()
    results = list(done.values())
    fh = open(resf, "a" if args.resume else "w")
    t0 = time.monotonic()

    def record(r):
        with lock:
            results.append(r)
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            n = len(results)
            if n % 250 == 0:
                counts = {}
                for x in results:
                    counts[x["class"]] = counts.get(x["class"], 0) + 1
                print(f"[{time.monotonic() - t0:7.0f} s] {n} runs {counts}", flush=True)

    jobs = []
    for i, c in enumerate(cmds):
        if (only is None or c in only) and f"f{i:05d}" not in done:
            jobs.append(("file", i, c))
    if args.cli and (only is None or "cli" in only):
        variants = cli_variants(cli_problem, random.Random(f"{args.seed}:cli"))
        variants = variants[:args.cli] if len(variants) >= args.cli else variants
        for j, v in enumerate(variants):
            if f"c{j:04d}" not in done:
                jobs.append(("cli", j, v))

    def work(job):
        try:
            if job[0] == "file":
                record(do_one(args, bases, job[1], job[2], args.keep_all))
            else:
                record(do_cli(args, job[1], job[2], cli_problem))
        except Exception as e:  # the harness must not stop the campaign
            import traceback
            traceback.print_exc()
            record({"id": f"err{job[1]}", "i": job[1], "command": str(job[2]), "class": "HARNESS",
                    "sub": str(e)[:200], "sig": "HARNESS", "ops": [], "rc": None,
                    "wall": 0, "maxrss_kb": 0, "kinds": [], "mut_keys": [], "base": "?",
                    "reasons": [], "stderr_head": "", "stdout_head": "", "argv": []})

    with ThreadPoolExecutor(max_workers=args.jobs) as ex:
        list(ex.map(work, jobs))
    fh.close()

    # ---- summary, findings, reproducers ----
    counts = {}
    for r in results:
        c = r["command"]
        counts.setdefault(c, {})
        counts[c][r["class"]] = counts[c].get(r["class"], 0) + 1
    groups = {}
    for r in results:
        if r["class"] in ("OK_RAN", "OK_REFUSED"):
            continue
        groups.setdefault((r["class"], r["sig"]), []).append(r)
    os.makedirs(repro_dir, exist_ok=True)
    findings = []
    order = {"PANIC": 0, "UNBOUNDED": 1, "EXIT0_ABSURD": 2, "UNCLEAR_ERROR": 3, "HARNESS": 4}
    for n, ((cls, sig), grp) in enumerate(sorted(groups.items(),
                                                 key=lambda kv: (order.get(kv[0][0], 9),
                                                                 -len(kv[1])))):
        rep, text = minimise(args, bases, grp)
        fid = f"{cls.lower()}_{n:03d}"
        repro = None
        if rep["command"] != "cli":
            repro = os.path.join(repro_dir, f"{fid}_{rep['command']}.toml")
            src = os.path.join(args.out, "files", f"{rep['id']}_{rep['command']}.toml")
            if text is not None:
                with open(repro, "w", encoding="utf-8") as f:
                    f.write(text)
            elif os.path.exists(src):
                shutil.copy(src, repro)
            argv = [args.binary] + [a.replace("FILE", repro) for a in rep["argv"]]
            argv = [(os.path.join(args.out, "out", fid) if k > 0 and argv[k - 1] == "--out" else a)
                    for k, a in enumerate(argv)]
        else:
            argv = [args.binary] + rep["argv"]
            argv = [(os.path.join(args.out, "out", fid) if a == "OUT" else a) for a in argv]
        findings.append({"id": fid, "class": cls, "sig": sig, "count": len(grp),
                         "commands": sorted({r["command"] for r in grp}),
                         "kinds": sorted({k for r in grp for k in r["kinds"]}),
                         "bases": sorted({r["base"] for r in grp})[:6],
                         "repro": repro, "argv": argv, "rc": rep["rc"], "sub": rep["sub"],
                         "mut_keys": rep["mut_keys"], "ops": rep["ops"],
                         "reasons": rep.get("reasons"), "minimised": rep.get("minimised", False),
                         "stderr_head": rep["stderr_head"], "stdout_head": rep["stdout_head"],
                         "members": [r["id"] for r in grp][:20]})
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump({"seed": args.seed, "count": args.count, "binary": args.binary,
                   "runs": len(results), "counts": counts, "findings": findings,
                   "elapsed_s": round(time.monotonic() - t0, 1)}, f, indent=1)
    with open(os.path.join(args.out, "findings.md"), "w") as f:
        f.write("| command | " + " | ".join(sorted(order) + ["OK_RAN", "OK_REFUSED"]) + " |\n")
        for c, d in sorted(counts.items()):
            f.write(f"| {c} | " + " | ".join(str(d.get(k, 0)) for k in sorted(order) +
                                            ["OK_RAN", "OK_REFUSED"]) + " |\n")
        for fd in findings:
            f.write(f"\n### {fd['id']} ({fd['count']}×, {','.join(fd['commands'])}, "
                    f"{','.join(fd['kinds'])})\n{fd['sig']}\n")
            f.write(f"    {' '.join(fd['argv'])}\n    exit {fd['rc']}; mutated {fd['mut_keys']}\n")
            for l in (fd["stderr_head"] or fd["stdout_head"]).splitlines()[:3]:
                f.write(f"    | {l[:220]}\n")
    shutil.rmtree(os.path.join(args.out, "runs"), ignore_errors=True)
    print(json.dumps(counts, indent=1))
    print(f"{len(findings)} findings; {os.path.join(args.out, 'findings.md')}")


if __name__ == "__main__":
    main()
