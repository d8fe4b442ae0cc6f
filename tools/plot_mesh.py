#!/usr/bin/env python3
"""Docs tool: renders exported skin meshes (OBJ or binary PLY from skin::WriteMesh) to a PNG
with matplotlib, flat Lambert shading with the light at the camera. Used to make the
pictures in docs/ (see docs/skins.md); not part of the simulator.

    pip install numpy matplotlib
    python3 tools/plot_mesh.py out.png a.obj [b.obj ...] [--titles A B] [--elev 55 --azim -60]
                               [--focus X Y Z RADIUS] [--box XMIN XMAX YMIN YMAX] [--cols 2]

--box keeps the triangles whose centroid lies in an x-y box (close-ups); --focus tints the triangles whose centroid lies within RADIUS of (X, Y, Z) (the hybrid
skin's focus sphere) so the convolution part shows.
"""
import argparse
import struct

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    return np.array(vertices), np.array(faces, dtype=int)


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        nv = int(next(h for h in header if h.startswith("element vertex")).split()[-1])
        nf = int(next(h for h in header if h.startswith("element face")).split()[-1])
        floats = 6 if any(h.endswith(" nx") for h in header) else 3
        data = np.frombuffer(f.read(nv * floats * 4), dtype="<f4").reshape(nv, floats)
        faces = np.empty((nf, 3), dtype=int)
        for i in range(nf):
            count, a, b, c = struct.unpack("<Biii", f.read(13))
            faces[i] = (a, b, c)
    return data[:, :3].astype(float), faces


def read_mesh(path):
    return read_ply(path) if path.lower().endswith(".ply") else read_obj(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output")
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("--titles", nargs="*")
    parser.add_argument("--elev", type=float, default=55.0)
    parser.add_argument("--azim", type=float, default=-60.0)
    parser.add_argument("--focus", type=float, nargs=4)
    parser.add_argument("--focus-panel", type=int, help="tint only this panel (0-based)")
    parser.add_argument("--cols", type=int, default=0)
    parser.add_argument("--size", type=float, default=6.0, help="inches per panel")
    parser.add_argument("--box", type=float, nargs=4, metavar=("XMIN", "XMAX", "YMIN", "YMAX"),
                        help="keep only triangles whose centroid lies in this x-y box (a close-up)")
    args = parser.parse_args()

    n = len(args.meshes)
    cols = args.cols or n
    rows = (n + cols - 1) // cols
    fig = plt.figure(figsize=(args.size * cols, args.size * rows), dpi=110)
    elev, azim = np.radians(args.elev), np.radians(args.azim)
    # direction from the scene towards the camera (matplotlib's view convention)
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    for k, path in enumerate(args.meshes):
        v, f = read_mesh(path)
        total = len(f)
        if args.box is not None:
            c = v[f].mean(axis=1)
            x0, x1, y0, y1 = args.box
            f = f[(c[:, 0] >= x0) & (c[:, 0] <= x1) & (c[:, 1] >= y0) & (c[:, 1] <= y1)]
            v_used = v[np.unique(f)]
        else:
            v_used = v
        tri = v[f]
        normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
        lambert = np.clip(normals @ eye, 0.0, 1.0)
        base = np.tile(np.array([0.86, 0.55, 0.50]), (len(f), 1))  # intestine pink
        if args.focus is not None and args.focus_panel in (None, k):
            centre, radius = np.array(args.focus[:3]), args.focus[3]
            inside = np.linalg.norm(tri.mean(axis=1) - centre, axis=1) < radius
            base[inside] = [0.45, 0.62, 0.85]
        colours = base * (0.25 + 0.75 * lambert[:, None])
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection(tri, facecolors=np.clip(colours, 0, 1), edgecolors="none", linewidths=0))
        lo, hi = v_used.min(axis=0), v_used.max(axis=0)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(np.maximum(hi - lo, 1e-6))
        ax.view_init(elev=args.elev, azim=args.azim)
        ax.set_axis_off()
        title = args.titles[k] if args.titles and k < len(args.titles) else path.split("/")[-1]
        ax.set_title(f"{title}\n{total} triangles", fontsize=11)
    fig.tight_layout()
    fig.savefig(args.output)


if __name__ == "__main__":
    main()
