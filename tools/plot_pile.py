#!/usr/bin/env python3
"""Draws the sphere chain of a viscera-sim trace: docs pictures of the final pile.

    tools/plot_pile.py TRACE.jsonl OUT.png [--time T ...] [--scene SCENE.toml]
                       [--tool-script CSV] [--title TEXT]

A DOCS-ONLY TOOL: it makes the pictures in docs/ (docs/fall_pile.png, docs/cavity_clearing.png;
commands in docs/contacts.md, "Pictures") and is not part of the build, the tests or the
simulator. It needs numpy and matplotlib, which the project does not otherwise use:
`pip install numpy matplotlib`.

TRACE.jsonl is `viscera-sim SCENE --trace TRACE.jsonl` (the frames' `t`, `spheres` and
`sphere_radius`). Each chosen frame (default: the last; `--time T` picks the frame nearest to T,
repeat it for several frames side by side) is drawn as two orthographic views, from above (x-y)
and from the front (x-z), with the spheres as discs to scale (radius = `sphere_radius`), nearer
ones drawn over farther ones, coloured by arc length (sphere index along the chain, start = dark
blue, end = yellow). With --scene, the plane, sphere, capsule and ellipsoid obstacles are outlined
and the tool ports marked; with --tool-script as well, each tool's tip at the frame's time is
drawn with its shaft from the port and its jaws open (white) or closed (red): the simulated tip
where the trace has it (`tool_tip`, viscera-sim writes it), else the script's target (where the
tool is asked to be, which the tip follows through the virtual coupling).
"""
import argparse
import csv
import json
import textwrap
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402
from matplotlib.patches import Circle, Ellipse  # noqa: E402


def read_frames(path, times):
    """The frames nearest to each of `times` (None: the last frame), in that order."""
    want = list(times) if times else [None]
    best = [None] * len(want)  # (|dt|, frame)
    last = None
    with open(path) as f:
        for line in f:
            if not line.strip():
                continue
            frame = json.loads(line)
            if "spheres" not in frame:
                sys.exit(f"{path}: frames have no 'spheres' (a scene without contacts?)")
            last = frame
            for i, t in enumerate(want):
                if t is None:
                    continue
                d = abs(frame["t"] - t)
                if best[i] is None or d < best[i][0]:
                    best[i] = (d, frame)
    if last is None:
        sys.exit(f"{path}: no frames")
    return [last if t is None else best[i][1] for i, t in enumerate(want)]


def read_script(path):
    """Tool script rows grouped by tool: {name: [(t, tip xyz, jaw), ...]} sorted by t."""
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(line for line in f if not line.lstrip().startswith("#")):
            tip = np.array([float(r["x"]), float(r["y"]), float(r["z"])])
            rows.setdefault(r["tool"], []).append((float(r["t"]), tip, float(r["jaw"])))
    for v in rows.values():
        v.sort(key=lambda row: row[0])
    return rows


def script_target(rows, t):
    """Linear interpolation of a tool's tip target and jaw at time t (held past the ends)."""
    if t <= rows[0][0]:
        return rows[0][1], rows[0][2]
    for (t0, p0, j0), (t1, p1, j1) in zip(rows, rows[1:]):
        if t <= t1:
            a = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
            return p0 + a * (p1 - p0), j0 + a * (j1 - j0)
    return rows[-1][1], rows[-1][2]


VIEWS = (("from above", 0, 1, 2, "x (m)", "y (m)"), ("from the front", 0, 2, 1, "x (m)", "z (m)"))


def draw_obstacles(ax, scene, u, v):
    """Outlines of the scene's obstacles projected on axes (u, v)."""
    style = dict(fill=False, color="0.45", lw=1.0, ls="--", zorder=0)
    for ob in scene.get("obstacle", []):
        kind = ob.get("kind")
        if kind == "plane":
            n = np.array(ob["normal"], float)
            p = np.array(ob["point"], float)
            if abs(n[u]) < 1e-9 and abs(n[v]) > 0.5:  # seen edge-on: a line
                ax.axhline(p[v], color="0.35", lw=1.5, zorder=0)
        elif kind in ("sphere", "ellipsoid"):
            c = np.array(ob["centre"], float)
            radii = [ob["radius"]] * 3 if kind == "sphere" else ob["radii"]
            ax.add_patch(Ellipse((c[u], c[v]), 2 * radii[u], 2 * radii[v], **style))
        elif kind == "capsule":
            a, b, r = np.array(ob["a"], float), np.array(ob["b"], float), ob["radius"]
            d = b[[u, v]] - a[[u, v]]
            if np.linalg.norm(d) > 1e-12:
                nrm = np.array([-d[1], d[0]]) / np.linalg.norm(d) * r
                for s in (1, -1):
                    ax.plot([a[u] + s * nrm[0], b[u] + s * nrm[0]], [a[v] + s * nrm[1], b[v] + s * nrm[1]],
                            color="0.45", lw=1.0, ls="--", zorder=0)
            for e in (a, b):
                ax.add_patch(Circle((e[u], e[v]), r, **style))
        # mesh obstacles (an SDF of an OBJ) are not drawn


def view_limits(frames, scene, u, v):
    """Common limits of one view over all frames (and the scene's cavity and ports)."""
    pts = [np.asarray(f["spheres"], float)[:, [u, v]] for f in frames]
    r = max(float(f["sphere_radius"]) for f in frames)
    lo = np.min([p.min(axis=0) for p in pts], axis=0) - 2 * r
    hi = np.max([p.max(axis=0) for p in pts], axis=0) + 2 * r
    if scene:
        for tool in scene.get("tool", []):
            port = np.array(tool["port"], float)[[u, v]]
            lo, hi = np.minimum(lo, port - r), np.maximum(hi, port + r)
        for ob in scene.get("obstacle", []):
            if ob.get("kind") == "ellipsoid" and ob.get("inside"):
                c, radii = np.array(ob["centre"], float), np.array(ob["radii"], float)
                lo = np.minimum(lo, (c - radii)[[u, v]])
                hi = np.maximum(hi, (c + radii)[[u, v]])
    pad = 0.03 * (hi - lo).max()
    return lo - pad, hi + pad


def draw_frame(fig, gs_col, frame, scene, script, cmap, head, limits):
    centres = np.asarray(frame["spheres"], float)
    r = float(frame["sphere_radius"])
    arc = np.linspace(0.0, 1.0, len(centres))
    for row, (name, u, v, depth, xl, yl) in enumerate(VIEWS):
        ax = fig.add_subplot(gs_col[row])
        # Painter's order: far first. From above, the viewer is at +z; from the front, at -y.
        order = np.argsort(centres[:, depth] if depth == 2 else -centres[:, depth])
        discs = EllipseCollection(np.full(len(centres), 2 * r), np.full(len(centres), 2 * r), np.zeros(len(centres)),
                                  units="xy", offsets=centres[order][:, [u, v]], offset_transform=ax.transData,
                                  cmap=cmap, edgecolors="k", linewidths=0.3, zorder=2)
        discs.set_array(arc[order])
        discs.set_clim(0.0, 1.0)
        ax.add_collection(discs)
        if scene:
            draw_obstacles(ax, scene, u, v)
            for tool in scene.get("tool", []):
                port = np.array(tool["port"], float)
                ax.plot(port[u], port[v], marker="v", color="k", ms=6, zorder=4)
                if script and tool["name"] in script:
                    tip, jaw = script_target(script[tool["name"]], frame["t"])
                    # the simulated tip where the trace has it: a row aimed at the tube
                    # (aim = tube, tube@S) was written where the tool comes from, not where it went
                    if tool["name"] in frame.get("tool_tip", {}):
                        tip = np.asarray(frame["tool_tip"][tool["name"]], float)
                    ax.plot([port[u], tip[u]], [port[v], tip[v]], color="0.2", lw=2.0, zorder=5)
                    ax.plot(tip[u], tip[v], marker="o", ms=7, zorder=6, mec="k",
                            mfc="red" if jaw < 0.5 else "white")
        lo, hi = limits[row]
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_xlabel(xl, fontsize=8)
        ax.set_ylabel(yl, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.set_title(f"{head if row == 0 else ''}{name}", fontsize=9)
        ax.grid(True, lw=0.3, alpha=0.5)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("trace")
    p.add_argument("out")
    p.add_argument("--time", type=float, action="append", help="frame nearest to this t (repeatable)")
    p.add_argument("--scene", help="scene TOML: outline obstacles, mark tool ports")
    p.add_argument("--tool-script", help="tool script CSV: draw the scripted tool targets (needs --scene)")
    p.add_argument("--label", action="append", help="caption of each --time frame (repeatable)")
    p.add_argument("--title", default="")
    a = p.parse_args()

    frames = read_frames(a.trace, a.time)
    scene = None
    if a.scene:
        with open(a.scene, "rb") as f:
            scene = tomllib.load(f)
    script = read_script(a.tool_script) if a.tool_script else None
    cmap = plt.get_cmap("viridis")

    # One column per frame (side by side), the two views one above the other, at the same scale
    # and limits in every column so that frames compare directly.
    nf = len(frames)
    limits = [view_limits(frames, scene, u, v) for _, u, v, _, _, _ in VIEWS]
    heights = [hi[1] - lo[1] for lo, hi in limits]
    width = limits[0][1][0] - limits[0][0][0]
    panel_w = 4.6
    fig_h = panel_w * sum(heights) / width + 2.2
    fig = plt.figure(figsize=(panel_w * nf + 1.2, fig_h), layout="constrained")
    grid = fig.add_gridspec(2, nf, height_ratios=heights)
    for i, frame in enumerate(frames):
        c = frame.get("contacts", {})
        mc = frame.get("min_clearance")
        label = a.label[i] + "\n" if a.label and i < len(a.label) else ""
        head = (f"{label}t = {frame['t']:.2f} s, {len(frame['spheres'])} spheres\ncontacts self {c.get('self', '?')}, "
                f"env {c.get('environment', '?')}, tool {c.get('tool', '?')}; min clearance "
                f"{'-' if mc is None else f'{mc * 1e3:.1f} mm'}\n")
        draw_frame(fig, [grid[0, i], grid[1, i]], frame, scene, script, cmap, head, limits)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, 1.0))
    fig.colorbar(sm, ax=fig.axes, shrink=0.5, label="arc length s / L (sphere index)")
    if a.title:
        fig.suptitle(textwrap.fill(a.title, 40 * nf + 20), fontsize=10)
    fig.savefig(a.out, dpi=110)
    times = ", ".join(f"{fr['t']:.2f}" for fr in frames)
    print(f"wrote {a.out}: {nf} frame(s), t = {times}")


if __name__ == "__main__":
    main()
