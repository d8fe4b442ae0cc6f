#!/usr/bin/env python3
"""Writes the scripted runs of running the bowel (scenes/bowel_run.toml, docs/training.md).

Hand over hand from the duodenojejunal end, the way a surgeon runs it: each grasper in turn
lifts the part it holds to a presentation point over the mesentery's root (its own side of it,
as high as the part's mesentery allows), so the next 5 cm hang free below it, off the pile.
The free grasper reaches for the bowel just past the part held (aim = tube@S, resolved when
the reach begins), slides 3 cm along it to the next part (resolved when the slide begins, against
the bowel as it hangs then: the way along the tube is free of other loops), looks (aim = grasp@S:
jaws beside another strand back off and reach again), closes on it,
lifts it to its own presentation point while the other lets go and backs off above its point.
The bowel runs through the two points and falls back on the pile behind them. The kinds:
  expert    one grasp every 5 cm, on the middle of each segment, jaws closed to 0.2 (a third
            of the grip: 6.7 N)
  rough     the expert's run, but some grasps shut the jaws (20 N) and one of them yanks the
            bowel 22 cm up
  careless  the expert's grip, but it jumps 20 cm at a few grasps (skipping three segments) and
            backs off 12 cm between grasps
With --seed N, an expert's run as one of a cohort of experts would do it, seeded: the run's
pace (SD 10 % around 1.6 s a grasp) and how far its graspers back off (2-4.5 cm) vary from
expert to expert, and each grasp's pace (SD 5 %) and its place in the segment (within 5 mm of
the middle) within a run. The runs of several seeds give a cohort's mean and SD for the pass
marks (tools/pass_marks.py).
The scene's mesentery (root, lengths), tool ports and camera are read from the scene file.
With --camera-out, the laparoscope follows the work, as an assistant holds it: at each grasp it
turns, from its port, to the point between the part about to be grasped and the part held, its
lens `insertion` past the port (viscera-sim --camera-script).
Usage: tools/bowel_run_script.py KIND [--scene scenes/bowel_run.toml] [--start 0.025] [--end M]
       [--seed N] [--out FILE] [--camera-out FILE]
"""
import argparse
import os
import random
import sys
import tomllib

STEP = 0.05  # m between grasps: one on the middle of each 5 cm segment
CYCLE = 1.6  # s per grasp
SIDE = 0.015  # m: each grasper's presentation point this far to its side of the root (x)
HEIGHT = 0.9  # of the part's mesentery length: how high a held part is presented
BACK = 0.03  # m: a grasper that let go backs off this far above its point
WALK = 0.03  # m: the free grasper reaches the bowel this far before the next part
# The grasps (counted from 0, grasp k on segment k) where the rough run shuts the jaws, and the
# one where it also yanks.
ROUGH_PINCH = (9, 19)
ROUGH_YANK = 19
# The grasps after which the careless run jumps 20 cm instead of 5, from the middle of a segment
# to the middle of the fourth after it (skipping three).
CARELESS_JUMPS = (9, 19, 29)
JUMP = 0.20


class Scene:
    def __init__(self, path):
        with open(path, "rb") as f:
            t = tomllib.load(f)
        self.length = t["intestine"]["length"]
        m = t["mesentery"]
        self.root = (m["root_start"], m["root_end"])
        self.lengths = m["lengths"]
        self.ports = {tool["name"]: tuple(tool["port"]) for tool in t["tool"]}
        c = t["camera"]
        self.camera_port = tuple(c["port"])
        self.camera_look = tuple(c["look_at"])
        self.insertion = c.get("insertion", 0.0)

    def tether(self, u):  # the mesentery's length at arc-length fraction u (piecewise linear)
        pts = self.lengths
        for (u0, l0), (u1, l1) in zip(pts, pts[1:]):
            if u <= u1:
                return l0 + (l1 - l0) * (u - u0) / (u1 - u0)
        return pts[-1][1]

    def present(self, tool, s):  # where `tool` presents the part at s (m)
        u = min(1.0, s / self.length)
        a, b = self.root
        r = [a[i] + u * (b[i] - a[i]) for i in range(3)]
        side = -SIDE if self.ports[tool][0] < 0 else SIDE
        return (r[0] + side, r[1], r[2] + HEIGHT * self.tether(u))


class Grasp:
    """One grasp of the run: where along the bowel (m), when its cycle starts (s) and how long
    its cycle takes against CYCLE (1 for the shipped runs)."""

    def __init__(self, s, t, pace):
        self.s, self.t, self.pace = s, t, pace


def plan(kind, start, end, seed=None):
    """The grasps in order, and how far a grasper that let go backs off (m). Seeded, the run's
    pace and back-off and each grasp's pace and place vary."""
    rng = random.Random(seed) if seed is not None else None
    back = 0.12 if kind == "careless" else BACK
    run_pace = 1.0
    if rng:
        run_pace = min(1.3, max(0.85, rng.gauss(1.0, 0.1)))
        back = rng.uniform(0.02, 0.045)
    grasps, t = [], 0.5
    for s in grasp_points(kind, start, end):
        pace, shift = run_pace, 0.0
        if rng:
            pace = max(0.85, run_pace * rng.gauss(1.0, 0.05))
            shift = rng.uniform(-0.005, 0.005)
        grasps.append(Grasp(s + shift, t, pace))
        t += CYCLE * pace
    return grasps, back


def camera_rows(scene, grasps):
    """The scope's eye and look-at at each grasp: turned toward the work in the 0.4 s before the
    free grasper reaches, and held until the next grasp's turn."""
    out = []

    def aim(target):
        d = [target[i] - scene.camera_port[i] for i in range(3)]
        n = sum(x * x for x in d) ** 0.5
        eye = tuple(scene.camera_port[i] + scene.insertion * d[i] / n for i in range(3))
        return eye, target

    out.append((0.0,) + aim(scene.camera_look))
    tools = sorted(scene.ports, key=lambda name: scene.ports[name][0])
    for k, g in enumerate(grasps):
        t, s = g.t, g.s
        me, other = tools[k % 2], tools[(k + 1) % 2]
        held = scene.present(other, grasps[k - 1].s) if k > 0 else scene.present(me, s)
        nxt = scene.present(me, s)
        # between the two presentation points, halfway down to the pile the free grasper reaches
        target = tuple(0.5 * (held[i] + nxt[i]) for i in range(3))
        target = (target[0], target[1], 0.5 * (target[2] + scene.camera_look[2]))
        out.append((t,) + out[-1][1:])
        out.append((t + 0.4 * g.pace,) + aim(target))
    return out


def grasp_points(kind, start, end):
    points, s, k = [], start, 0
    while s <= end + 1e-9:
        points.append(s)
        jump = kind == "careless" and k in CARELESS_JUMPS
        s += JUMP if jump else STEP
        k += 1
    return points


def rows(scene, kind, grasps, back):
    out = []

    def row(t, tool, p, jaw, aim):
        out.append((round(t, 4), tool, tuple(p), jaw, aim))

    def up(p, dz):
        return (p[0], p[1], p[2] + dz)

    tools = sorted(scene.ports, key=lambda name: scene.ports[name][0])  # left (-x) first
    held = {}  # tool -> (presentation point, jaw) of what it holds
    parked = {}  # tool -> where it waits, jaws open
    for tool in tools:  # both start above their presentation points, jaws open
        parked[tool] = up(scene.present(tool, grasps[0].s), 0.08)
        row(0.0, tool, parked[tool], 1.0, "point")
    for k, g in enumerate(grasps):
        s = g.s

        def at(offset):  # a moment of this grasp's cycle, at its pace
            return g.t + offset * g.pace

        me, other = tools[k % 2], tools[(k + 1) % 2]
        shut = kind == "rough" and k in ROUGH_PINCH
        jaw = 0.0 if shut else 0.2
        aim = "tube@%.6f" % min(1.0, s / scene.length)
        port = scene.ports[me]
        row(at(0.0), me, parked[me], 1.0, "point")  # waits above its point, for the bowel to settle
        row(at(0.2), me, parked[me], 1.0, "point")
        # reaches for the hanging part just past the one held, and slides along it to the next
        row(at(0.45), me, port, 1.0, "tube@%.6f" % max(0.0, (s - WALK) / scene.length))
        row(at(0.65), me, port, 1.0, "tube@%.6f" % max(0.0, (s - WALK / 2) / scene.length))
        row(at(0.85), me, port, 1.0, aim)
        # aimed again as the jaws arrive (resolved 0.85 s into the cycle, against the bowel as it hangs
        # then), so that they close where the part is, not where it was 0.4 s before
        row(at(1.0), me, port, 1.0, aim)
        # and looked at as they close (a grasp row, 10 ms before they take the part): jaws beside
        # another strand (the part swung away) back off and reach again
        row(at(1.04), me, port, 1.0, "grasp@%.6f" % min(1.0, s / scene.length))
        row(at(1.05), me, (0.0, 0.0, 0.0), jaw, "offset")  # closes on it
        if other in held:  # the other hand lets go and backs off above its point
            p, j = held.pop(other)
            row(at(1.05), other, p, j, "point")
            row(at(1.25), other, p, 1.0, "point")
            parked[other] = up(p, back)
            row(at(1.5), other, parked[other], 1.0, "point")
        spot = scene.present(me, s)
        if kind == "rough" and k == ROUGH_YANK:
            row(at(1.3), me, (0.0, 0.0, 0.22), jaw, "offset")  # yanks it up
            row(at(1.6), me, spot, jaw, "point")
        else:
            row(at(1.5), me, spot, jaw, "point")  # presents it
        held[me] = (spot, jaw)
    # the last grasper lets go and backs off
    t = grasps[-1].t + CYCLE * grasps[-1].pace
    last = tools[(len(grasps) - 1) % 2]
    p, j = held[last]
    row(t, last, p, j, "point")
    row(t + 0.3, last, p, 1.0, "point")
    row(t + 0.8, last, up(p, back), 1.0, "point")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=("expert", "rough", "careless"))
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--scene", default=os.path.join(here, "..", "scenes", "bowel_run.toml"))
    ap.add_argument("--start", type=float, default=0.025, help="first grasp (m from s = 0)")
    ap.add_argument("--end", type=float, default=None, help="last grasp at most (m)")
    ap.add_argument("--seed", type=int, default=None,
                    help="an expert of a cohort: vary the pace, back-off and places (expert only)")
    ap.add_argument("--out", default=None, help="CSV to write (default: stdout)")
    ap.add_argument("--camera-out", default=None,
                    help="also write the laparoscope's moves (t,ex,ey,ez,cx,cy,cz) to this CSV")
    a = ap.parse_args()
    if a.seed is not None and a.kind != "expert":
        ap.error("--seed varies the expert's run only")
    scene = Scene(a.scene)
    end = a.end if a.end is not None else scene.length - 0.025
    grasps, back = plan(a.kind, a.start, end, a.seed)
    points = [g.s for g in grasps]
    frames = rows(scene, a.kind, grasps, back)
    frames.sort(key=lambda r: (r[1], r[0]))
    lines = [
        "# Running the bowel, %s run (tools/bowel_run_script.py %s%s): %d grasps from %.3f m to "
        "%.3f m of the bowel, one every %.1f cm%s." % (
            a.kind, a.kind, "" if a.seed is None else " --seed %d" % a.seed, len(points), points[0], points[-1], 100 * STEP,
            {"expert": "", "rough": "; shuts the jaws at grasps %s and yanks at grasp %d" % (
                ", ".join(map(str, ROUGH_PINCH)), ROUGH_YANK),
             "careless": "; jumps 20 cm after grasps %s" % ", ".join(map(str, CARELESS_JUMPS))}[a.kind]),
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
    if a.camera_out:
        lines = ["# The laparoscope of the %s run (tools/bowel_run_script.py %s --camera-out)."
                 % (a.kind, a.kind), "t,ex,ey,ez,cx,cy,cz"]
        for t, eye, target in camera_rows(scene, grasps):
            lines.append("%g,%s" % (t, ",".join("%.4f" % v for v in eye + target)))
        with open(a.camera_out, "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
