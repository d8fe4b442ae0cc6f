// The viewer page's intestine: the parametric skin (src/skin/parametric_skin.h) rebuilt from
// the control points of a skeleton state, with the server's culling and levels of detail. The
// page's script is this file followed by viewer.js (client/CMakeLists.txt joins them).
'use strict';

const ViewerTube = (() => {
  // ---- the intestine: uniform Catmull-Rom curve with reflected end points ----------------
  // coordinate a of control point k, the end points reflected beyond the ends
  function At(q, n, k, a) {
    if (k < 0) return 2 * q[a] - q[3 + a];
    if (k >= n) return 2 * q[3 * (n - 1) + a] - q[3 * (n - 2) + a];
    return q[3 * k + a];
  }
  function CurvePoint(q, n, s, out, at = 0) {
    const x = Math.min(Math.max(s, 0), 1) * (n - 1);
    const j = Math.min(Math.floor(x), n - 2);
    const u = x - j;
    const u2 = u * u, u3 = u2 * u;
    const w0 = -0.5 * u3 + u2 - 0.5 * u, w1 = 1.5 * u3 - 2.5 * u2 + 1;
    const w2 = -1.5 * u3 + 2 * u2 + 0.5 * u, w3 = 0.5 * u3 - 0.5 * u2;
    for (let a = 0; a < 3; ++a) {
      out[at + a] = w0 * At(q, n, j - 1, a) + w1 * At(q, n, j, a) + w2 * At(q, n, j + 1, a) + w3 * At(q, n, j + 2, a);
    }
    return u;
  }
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };

  class Tube {
    constructor(t) {
      this.t = t;
      this.rings = (t.points - 1) * t.rings_per_segment + 1;
      this.sides = t.sides;
      this.cap = t.cap_rings;
      const vertices = 2 * (1 + (this.cap - 1) * this.sides) + this.rings * this.sides;
      this.positions = new Float32Array(3 * vertices);
      this.normals = new Float32Array(3 * vertices);
      this.texture = new Float32Array(3 * vertices);
      this.indices = this.Triangles();
      this.first_normal = null;  // kept from build to build: the rings do not spin
      // per ring: centre, tangent, normal (3 each), radius, curve parameter u; reused
      const K = this.rings;
      this.centres = new Float64Array(3 * K);
      this.tangents = new Float64Array(3 * K);
      this.frames = new Float64Array(3 * K);
      this.radii = new Float64Array(K);
      this.ahead = new Float64Array(3);
      this.behind = new Float64Array(3);
      this.cos = Float64Array.from({length: this.sides}, (_, j) => Math.cos(2 * Math.PI * j / this.sides));
      this.sin = Float64Array.from({length: this.sides}, (_, j) => Math.sin(2 * Math.PI * j / this.sides));
      this.at = 0;
    }
    // rows of `sides` vertices from the front pole's ring to the back pole's, as TubeRays
    Triangles() {
      const m = this.sides, rows = 2 * (this.cap - 1) + this.rings;
      const out = [];
      const v = (row, j) => 1 + row * m + (j % m);
      for (let j = 0; j < m; ++j) out.push(0, v(0, j + 1), v(0, j));  // front pole fan
      for (let row = 0; row + 1 < rows; ++row) {
        for (let j = 0; j < m; ++j) {
          out.push(v(row, j), v(row, j + 1), v(row + 1, j + 1), v(row, j), v(row + 1, j + 1), v(row + 1, j));
        }
      }
      const back = 1 + rows * m;
      for (let j = 0; j < m; ++j) out.push(back, v(rows - 1, j), v(rows - 1, j + 1));
      return new Uint32Array(out);
    }
    Put(x, y, z, dx, dy, dz, tx, ty, tz) {
      const i = 3 * this.at++, P = this.positions, N = this.normals, T = this.texture;
      P[i] = x; P[i + 1] = y; P[i + 2] = z;
      N[i] = dx; N[i + 1] = dy; N[i + 2] = dz;
      T[i] = tx; T[i + 1] = ty; T[i + 2] = tz;
    }
    // ring k's vertices; theta: polar angle from the end's axis (caps, end -1 or 1), or none
    Ring(k, theta, end) {
      const C = this.centres, Tg = this.tangents, F = this.frames, m = this.sides;
      const i = 3 * k, r = this.radii[k], along0 = k / (this.rings - 1) * this.t.length;
      const tx = Tg[i], ty = Tg[i + 1], tz = Tg[i + 2], nx = F[i], ny = F[i + 1], nz = F[i + 2];
      const bx = ty * nz - tz * ny, by = tz * nx - tx * nz, bz = tx * ny - ty * nx;  // tangent x normal
      const cap = theta !== undefined, st = cap ? Math.sin(theta) : 1, ct = cap ? Math.cos(theta) : 0;
      const e = cap ? end * ct : 0, along = cap ? end * r * ct : 0;
      for (let j = 0; j < m; ++j) {
        const cp = this.cos[j], sp = this.sin[j];
        let dx = cp * nx + sp * bx, dy = cp * ny + sp * by, dz = cp * nz + sp * bz;
        if (cap) {
          dx = st * dx + e * tx; dy = st * dy + e * ty; dz = st * dz + e * tz;
        }
        this.Put(C[i] + r * dx, C[i + 1] + r * dy, C[i + 2] + r * dz, dx, dy, dz, along0 + along, r * cp, r * sp);
      }
    }
    Pole(k, end) {
      const i = 3 * k, C = this.centres, Tg = this.tangents, r = this.radii[k];
      const dx = end * Tg[i], dy = end * Tg[i + 1], dz = end * Tg[i + 2];
      this.Put(C[i] + r * dx, C[i + 1] + r * dy, C[i + 2] + r * dz, dx, dy, dz,
               k / (this.rings - 1) * this.t.length + end * r, 0, 0);
    }
    Build(q) {
      const t = this.t, n = t.points, K = this.rings, C = this.centres, Tg = this.tangents, F = this.frames;
      const ahead = this.ahead, behind = this.behind, h = 1e-4;
      for (let k = 0; k < K; ++k) {
        const s = k / (K - 1), i = 3 * k;
        const u = CurvePoint(q, n, s, C, i);
        CurvePoint(q, n, Math.min(s + h, 1), ahead);
        CurvePoint(q, n, Math.max(s - h, 0), behind);
        let x = ahead[0] - behind[0], y = ahead[1] - behind[1], z = ahead[2] - behind[2];
        const l = Math.hypot(x, y, z) || 1;
        Tg[i] = x / l; Tg[i + 1] = y / l; Tg[i + 2] = z / l;
        const c = Math.cos(Math.PI * u);
        this.radii[k] = t.radius_min + c * c * (t.radius_max - t.radius_min);
      }
      // frames by double reflection (Wang et al. 2008), from the last build's first normal
      let normal = this.first_normal;
      if (normal === null) {
        const a = [Math.abs(Tg[0]), Math.abs(Tg[1]), Math.abs(Tg[2])];
        normal = a[0] <= a[1] && a[0] <= a[2] ? [1, 0, 0] : a[1] <= a[2] ? [0, 1, 0] : [0, 0, 1];
      }
      const along = normal[0] * Tg[0] + normal[1] * Tg[1] + normal[2] * Tg[2];
      normal = unit([normal[0] - along * Tg[0], normal[1] - along * Tg[1], normal[2] - along * Tg[2]]);
      this.first_normal = normal;
      F[0] = normal[0]; F[1] = normal[1]; F[2] = normal[2];
      for (let k = 1; k < K; ++k) {
        const i = 3 * k, o = i - 3;
        // r = the last normal reflected in the plane normal to v1 = the step between centres,
        // tl = the last tangent reflected so, then r reflected in the plane normal to t - tl
        const v1x = C[i] - C[o], v1y = C[i + 1] - C[o + 1], v1z = C[i + 2] - C[o + 2];
        const c1 = v1x * v1x + v1y * v1y + v1z * v1z;
        let rx = F[o], ry = F[o + 1], rz = F[o + 2], lx = Tg[o], ly = Tg[o + 1], lz = Tg[o + 2];
        if (c1 > 0) {
          const a = 2 * (v1x * rx + v1y * ry + v1z * rz) / c1, b = 2 * (v1x * lx + v1y * ly + v1z * lz) / c1;
          rx -= a * v1x; ry -= a * v1y; rz -= a * v1z;
          lx -= b * v1x; ly -= b * v1y; lz -= b * v1z;
        }
        const v2x = Tg[i] - lx, v2y = Tg[i + 1] - ly, v2z = Tg[i + 2] - lz;
        const c2 = v2x * v2x + v2y * v2y + v2z * v2z;
        if (c2 > 0) {
          const a = 2 * (v2x * rx + v2y * ry + v2z * rz) / c2;
          rx -= a * v2x; ry -= a * v2y; rz -= a * v2z;
        }
        const l = Math.hypot(rx, ry, rz) || 1;
        F[i] = rx / l; F[i + 1] = ry / l; F[i + 2] = rz / l;
      }
      this.at = 0;
      const cap = this.cap;
      this.Pole(0, -1);
      for (let i = 1; i < cap; ++i) this.Ring(0, Math.PI / 2 * i / cap, -1);
      for (let k = 0; k < K; ++k) this.Ring(k);
      for (let i = cap - 1; i >= 1; --i) this.Ring(K - 1, Math.PI / 2 * i / cap, 1);
      this.Pole(K - 1, 1);
    }
  }

  return {Tube, CurvePoint, sub, cross, unit};
})();
