#!/usr/bin/env python3
"""Turns a Google Benchmark JSON report into the Markdown table docs/benchmarks.md prints.

Usage: bench/report_table.py NAME REPORT.json
  NAME: cavity, fall, mesentery, mechanics, mesh-sdf, skins or render (the sections of
  docs/benchmarks.md); any other name prints every row with its time and counters.

Run by bench/report.sh, which also prints the machine, commit and load above each table. Times
are the benchmark's CPU time (its thread's, or the process's where the benchmark says so); with
--benchmark_repetitions the median of the repetitions is taken.
"""

import json
import re
import sys

TO_US = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}


def base_name(name):
    """The benchmark's name without the harness's suffixes (/process_time, /real_time, ...)."""
    return re.sub(r"(/(process_time|real_time|manual_time|min_time:[^/]*|repeats:\d+|iterations:\d+))+$",
                  "", name)


def load(path):
    """Rows by name: the median aggregate where there is one, else the (last) run."""
    runs, medians = {}, {}
    for b in json.load(open(path))["benchmarks"]:
        name = base_name(b.get("run_name", b["name"]))
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                medians[name] = b
        else:
            runs[name] = b
    runs.update(medians)
    return runs


def cpu_us(b):
    return b["cpu_time"] * TO_US[b.get("time_unit", "ns")]


def fmt(x, digits=3):
    """A figure to about DIGITS significant digits, without exponent."""
    if x is None:
        return ""
    if x == int(x) and abs(x) < 1000:
        return str(int(x))  # counts: sub-steps, iterations
    if abs(x) >= 10000:
        return f"{x:,.0f}".replace(",", " ")
    if abs(x) >= 10 ** (digits - 1):
        return f"{x:.0f}"
    decimals = max(0, digits - 1 - int(f"{abs(x):e}".split("e")[1]))
    return f"{x:.{decimals}f}"


def table(header, rows, align=None):
    align = align or ["---"] + ["---:"] * (len(header) - 1)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def arg(name, key):
    m = re.search(rf"/{key}:(\d+)", name)
    return int(m.group(1)) if m else None


def mechanics(rows):
    sizes = sorted({arg(n, "n") or int(n.split("/")[1]) for n in rows if "/" in n and "RhsCopy" not in n})

    def get(name, f):
        return f(rows[name]) if name in rows else None

    out = []
    for n in sizes:
        out.append([
            n,
            fmt(get(f"BM_FallImplicit/n:{n}/cholmod:0", cpu_us)),
            fmt(get(f"BM_FallImplicit/n:{n}/cholmod:1", cpu_us)),
            fmt(get(f"BM_FallRk4Stable/{n}", lambda b: b["substeps"])),
            fmt(get(f"BM_FallRk4Stable/{n}", cpu_us)),
            fmt(get(f"BM_Rk4OneSubstep/{n}", cpu_us)),
            fmt(get(f"BM_Forces/n:{n}/jacobians:0", lambda b: cpu_us(b) * 1e3 / n)),
            fmt(get(f"BM_Forces/n:{n}/jacobians:1", lambda b: cpu_us(b) * 1e3 / n)),
            fmt(get(f"BM_MassSolve/n:{n}/cholmod:0", lambda b: cpu_us(b) * 1e3 / n)),
            fmt(get(f"BM_MassSolve/n:{n}/cholmod:1", lambda b: cpu_us(b) * 1e3 / n)),
        ])
    return table(["n", "implicit, block band (µs)", "implicit, CHOLMOD (µs)", "RK4 stable: sub-steps",
                  "RK4 stable: step (µs)", "RK4, 1 sub-step (µs)", "forces (ns per point)",
                  "forces + Jacobians (ns/pt)", "mass solve, banded (ns/pt)",
                  "mass solve, CHOLMOD (ns/pt)"], out)


CONTACT_ROWS = [
    ("BM_CavityClearing/rate:100", "cavity clearing, 100 Hz (2 x 5 ms sub-steps)"),
    ("BM_CavityClearing/rate:1000", "cavity clearing, 1 kHz"),
    ("BM_FallWhole/n:250/self:1", "whole fall (n = 250, 3 s from the coil)"),
    ("BM_FallSettled/n:250/self:1", "settled pile (n = 250)"),
    ("BM_FallWhole/n:250/self:0", "whole fall, self-contacts off"),
    ("BM_FallSettled/n:250/self:0", "settled pile, self-contacts off"),
    ("BM_PaperCoilFall/rate:100", "the peers' coil, 100 Hz"),
    ("BM_PaperCoilFall/rate:1000", "the peers' coil, 1 kHz"),
    ("BM_FallWholeLimiterOnly/n:250", "whole fall, limiter and law alone"),
    ("BM_CavityMesentery/term:0", "settled cavity, one step"),
    ("BM_CavityMesentery/term:1", "mesentery term alone, every tether taut"),
]


def contacts(rows, only=None):
    out = []
    labels = dict(CONTACT_ROWS)
    names = [n for n, _ in CONTACT_ROWS if n in rows]
    names += sorted(n for n in rows if n not in labels)  # other sizes, when filtered in
    for name in names:
        if only and not name.startswith(only):
            continue
        b = rows[name]
        per_step = b.get("us_per_step")
        if per_step is None:  # the mesentery rows: one iteration is the work itself
            per_step = cpu_us(b)
        out.append([
            labels.get(name, name), fmt(per_step), fmt(b.get("p99_us")), fmt(b.get("ms_per_sim_s")),
            fmt(b.get("realtime_x")) + ("x" if "realtime_x" in b else ""),
            fmt(b.get("substeps")), fmt(b.get("cg_per_substep")), fmt(b.get("deepest_pct_r")),
            fmt(b.get("x_pybullet")) + ("x" if "x_pybullet" in b else ""),
        ])
    return table(["row", "µs per step (mean)", "p99 (µs)", "ms per simulated s", "real time",
                  "sub-steps per step", "CG per sub-step", "deepest pair (% of R)",
                  "x pybullet"], out)


def mesh_sdf(rows):
    out = []
    for res in sorted({arg(n, "resolution") for n in rows}):
        brute = rows.get(f"BM_LiverField/hierarchy:0/resolution:{res}")
        tree = rows.get(f"BM_LiverField/hierarchy:1/resolution:{res}")
        b = brute and cpu_us(brute) / 1e3
        t = tree and cpu_us(tree) / 1e3
        out.append([res, fmt((brute or tree)["samples"]), f"{fmt(b)} ms" if b else "(not run)",
                    f"{fmt(t)} ms" if t else "", fmt(b / t, 2) if b and t else ""])
    return table(["resolution", "grid points", "brute force", "hierarchy", "ratio"], out)


def skins(rows):
    out = []
    for name, b in rows.items():
        out.append([f"`{name}`", fmt(b.get("triangles")), fmt(b.get("meshes/s")),
                    fmt(b.get("evals/vertex"))])
    return table(["benchmark", "triangles", "meshes/s", "field evaluations per vertex"], out)


def render(rows):
    skins_ = ["parametric", "convolution", "implicit", "hybrid"]
    out = []
    for name, b in rows.items():
        a = [int(x) for x in name.split("/")[1:7]]
        skin, w, h, sides, textures, camera = a
        look = ("textured" if textures else "plain") + (", scope" if camera else ", framing camera")
        out.append([skins_[skin] + (f" ({sides})" if sides else ""), f"{w}x{h}", look,
                    f"{b['triangles'] / 1e3:.0f}k", fmt(b["skin_ms"]), fmt(b["render_ms"]),
                    fmt(b["encode_ms"]), fmt(b["cpu_ms"]), fmt(b["frame fps"]), fmt(b["jpeg_kB"])])
    return table(["skin (sides)", "size", "look", "triangles drawn", "skin (ms)", "render (ms)",
                  "encode (ms)", "frame, process CPU (ms)", "fps", "JPEG (kB)"], out,
                 ["---", "---", "---"] + ["---:"] * 7)


def generic(rows):
    keys = sorted({k for b in rows.values() for k, v in b.items()
                   if isinstance(v, (int, float)) and k not in (
                       "family_index", "per_family_instance_index", "repetitions",
                       "repetition_index", "threads", "iterations", "real_time", "cpu_time")})
    out = [[f"`{n}`", fmt(cpu_us(b))] + [fmt(b.get(k)) for k in keys] for n, b in rows.items()]
    return table(["benchmark", "CPU (µs)"] + keys, out)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    name, rows = argv[1], load(argv[2])
    if not rows:
        print(f"report_table: no rows in {argv[2]}", file=sys.stderr)
        return 1
    formatters = {
        "mechanics": mechanics, "fall": contacts, "mesentery": contacts, "mesh-sdf": mesh_sdf, "skins": skins,
        "render": render, "cavity": lambda r: contacts(r, "BM_CavityClearing"),
    }
    print(formatters.get(name, generic)(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
