#!/usr/bin/env python3
"""Writes the scripted runs of running the bowel (scenes/bowel_run.toml, docs/training.md).

Hand over hand from the duodenojejunal end: the free grasper reaches for the bowel a step
further along (aim = tube@S, resolved when its reach begins, against the bowel as the holding
grasper left it), closes, the other lets go, the new one lifts what it holds (aim = offset) and
the free one backs off. The kinds:
  expert    one grasp every 4.5 cm, jaws closed to 0.2 (a third of the grip: 6.7 N), 3 cm lifts
  rough     the expert's run, but some grasps shut the jaws (20 N) and one of them yanks the
            bowel 22 cm up
  careless  the expert's grip, but it jumps 18 cm at a few grasps (skipping segments) and backs
            off 12 cm between grasps
Usage: tools/bowel_run_script.py KIND [--length 4.5] [--start 0.02] [--end M] [--out FILE]
"""
import argparse
import sys

PORTS = {"left": (-0.08, -0.10, 0.30), "right": (0.08, -0.10, 0.30)}
START = {"left": (-0.08, -0.05, 0.22), "right": (0.08, -0.05, 0.22)}
STEP = 0.045  # m between grasps
CYCLE = 1.6  # s per grasp
# The grasps (counted from 0) where the rough run shuts the jaws, and the one where it also yanks.
ROUGH_PINCH = (6, 14)
ROUGH_YANK = 14
# The grasps after which the careless run jumps 18 cm (four steps) instead of 4.5.
CARELESS_JUMPS = (5, 15, 30)


def grasp_points(kind, start, end):
    points, s, k = [], start, 0
    while s <= end + 1e-9:
        points.append(s)
        jump = kind == "careless" and k in CARELESS_JUMPS
        s += 4 * STEP if jump else STEP
        k += 1
    return points


def rows(kind, length, start, end):
    out = []

    def row(t, tool, p, jaw, aim):
        out.append((round(t, 4), tool, p, jaw, aim))

    points = grasp_points(kind, start, end)
    tools = ("left", "right")
    lift = 0.03
    back = 0.12 if kind == "careless" else 0.03
    for tool in tools:  # both start over their ports' side of the cavity, jaws open
        row(0.0, tool, START[tool], 1.0, "point")
    for k, s in enumerate(points):
        t = 0.5 + k * CYCLE
        me, other = tools[k % 2], tools[(k + 1) % 2]
        shut = kind == "rough" and k in ROUGH_PINCH
        jaw = 0.0 if shut else 0.2
        aim = "tube@%.6f" % min(1.0, s / length)
        if k >= 2:  # waits where it backed off, for the bowel to settle in the other's jaws
            row(t, me, (0.0, 0.0, lift + back), 1.0, "offset")
        elif k == 1:  # waits where it started
            row(t, me, START[me], 1.0, "point")
        row(t + 0.6, me, PORTS[me], 1.0, aim)  # reaches the next part of the bowel
        row(t + 0.9, me, (0.0, 0.0, 0.0), jaw, "offset")  # closes on it
        if k > 0:  # the other hand lets go and backs off
            row(t + 0.9, other, (0.0, 0.0, lift), out_jaw[other], "offset")
            row(t + 1.1, other, (0.0, 0.0, lift), 1.0, "offset")
            row(t + 1.4, other, (0.0, 0.0, lift + back), 1.0, "offset")
        if kind == "rough" and k == ROUGH_YANK:
            row(t + 1.2, me, (0.0, 0.0, 0.22), jaw, "offset")  # yanks it up
            row(t + 1.5, me, (0.0, 0.0, lift), jaw, "offset")
        else:
            row(t + 1.5, me, (0.0, 0.0, lift), jaw, "offset")  # lifts it
        out_jaw[me] = jaw
    t = 0.5 + len(points) * CYCLE
    last = tools[(len(points) - 1) % 2]
    row(t, last, (0.0, 0.0, 0.04), out_jaw[last], "offset")
    row(t + 0.3, last, (0.0, 0.0, 0.04), 1.0, "offset")
    row(t + 0.8, last, (0.0, 0.0, 0.08), 1.0, "offset")
    return out, points


out_jaw = {}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=("expert", "rough", "careless"))
    ap.add_argument("--length", type=float, default=4.5, help="bowel length (m)")
    ap.add_argument("--start", type=float, default=0.02, help="first grasp (m from s = 0)")
    ap.add_argument("--end", type=float, default=None, help="last grasp at most (m)")
    ap.add_argument("--out", default=None, help="CSV to write (default: stdout)")
    a = ap.parse_args()
    end = a.end if a.end is not None else a.length - 0.02
    frames, points = rows(a.kind, a.length, a.start, end)
    frames.sort(key=lambda r: (r[1], r[0]))
    lines = [
        "# Running the bowel, %s run (tools/bowel_run_script.py %s): %d grasps from %.3f m to "
        "%.3f m of the bowel, one every %.1f cm%s." % (
            a.kind, a.kind, len(points), points[0], points[-1], 100 * STEP,
            {"expert": "", "rough": "; shuts the jaws at grasps %s and yanks at grasp %d" % (
                ", ".join(map(str, ROUGH_PINCH)), ROUGH_YANK),
             "careless": "; jumps 18 cm after grasps %s" % ", ".join(map(str, CARELESS_JUMPS))}[a.kind]),
        "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim",
    ]
    for t, tool, p, jaw, aim in frames:
        lines.append("%g,%s,%.4f,%.4f,%.4f,1,0,0,0,%g,%s" % (t, tool, p[0], p[1], p[2], jaw, aim))
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
