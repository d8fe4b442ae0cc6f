// The viewer page's renderer: draws a session in WebGL2 from its skeleton states, as the
// server's OSMesa renderer draws its frames (src/render): the same shaders (the scene sends
// them), the same static geometry and materials, the laparoscope's matrices and light; the
// intestine is the parametric skin (viewer_tube.js, which comes first in the page's script)
// rebuilt from the control points, interpolated between skeleton messages, at the display's rate.
// Plain WebGL2, no library: the server's shaders run unchanged and the page loads nothing else.
'use strict';

const Viewer = (() => {
  const {Tube, CurvePoint, sub, cross, unit} = ViewerTube;

  // ---- GL --------------------------------------------------------------------------------
  class Mesh {
    constructor(gl) {
      this.gl = gl;
      this.vao = gl.createVertexArray();
      this.buffers = [gl.createBuffer(), gl.createBuffer(), gl.createBuffer()];
      this.sizes = [-1, -1, -1];  // bytes each buffer holds
      this.index = gl.createBuffer();
      this.count = 0;
      gl.bindVertexArray(this.vao);
      this.buffers.forEach((b, location) => {
        gl.bindBuffer(gl.ARRAY_BUFFER, b);
        gl.enableVertexAttribArray(location);
        gl.vertexAttribPointer(location, 3, gl.FLOAT, false, 0, 0);
      });
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.index);
      gl.bindVertexArray(null);
    }
    // positions, normals, texture points (or null: the positions) and triangles (or null: those
    // before); a buffer of the same size is written over, not made again
    Upload(positions, normals, texture, indices, dynamic) {
      const gl = this.gl, usage = dynamic ? gl.DYNAMIC_DRAW : gl.STATIC_DRAW;
      [positions, normals, texture || positions].forEach((data, k) => {
        const array = data instanceof Float32Array ? data : new Float32Array(data);
        gl.bindBuffer(gl.ARRAY_BUFFER, this.buffers[k]);
        if (dynamic && this.sizes[k] === array.byteLength) {
          gl.bufferSubData(gl.ARRAY_BUFFER, 0, array);
        } else {
          gl.bufferData(gl.ARRAY_BUFFER, array, usage);
          this.sizes[k] = array.byteLength;
        }
      });
      if (indices !== null) {
        gl.bindVertexArray(this.vao);
        gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices instanceof Uint32Array ? indices : new Uint32Array(indices), usage);
        gl.bindVertexArray(null);
        this.count = indices.length;
      }
    }
    // new positions and normals of as many vertices as before
    Move(positions, normals) {
      const gl = this.gl;
      [positions, normals].forEach((data, k) => {
        gl.bindBuffer(gl.ARRAY_BUFFER, this.buffers[k]);
        gl.bufferSubData(gl.ARRAY_BUFFER, 0, data);
      });
    }
    // a fourth attribute (location 3, 3 floats a vertex) from `buffer`
    Attribute(buffer) {
      const gl = this.gl;
      gl.bindVertexArray(this.vao);
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
      gl.enableVertexAttribArray(3);
      gl.vertexAttribPointer(3, 3, gl.FLOAT, false, 0, 0);
      gl.bindVertexArray(null);
    }
    // the first `count` of `indices` as the triangles, into the index buffer made before
    Triangles(indices, count) {
      const gl = this.gl;
      gl.bindVertexArray(this.vao);
      gl.bufferSubData(gl.ELEMENT_ARRAY_BUFFER, 0, indices, 0, count);
      gl.bindVertexArray(null);
      this.count = count;
    }
    Draw() {
      if (this.count === 0) return;
      this.gl.bindVertexArray(this.vao);
      this.gl.drawElements(this.gl.TRIANGLES, this.count, this.gl.UNSIGNED_INT, 0);
    }
  }

  function Compile(gl, vertex, fragment, captured = null) {
    const shader = (type, text) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, text);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const program = gl.createProgram();
    gl.attachShader(program, shader(gl.VERTEX_SHADER, vertex));
    gl.attachShader(program, shader(gl.FRAGMENT_SHADER, fragment));
    if (captured !== null) gl.transformFeedbackVaryings(program, captured, gl.SEPARATE_ATTRIBS);
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
    const names = ['u_view', 'u_projection', 'u_albedo', 'u_ambient', 'u_specular', 'u_shininess', 'u_sheen',
                   'u_sheen_shininess', 'u_metallic', 'u_light_range', 'u_opacity', 'u_vessel', 'u_spot'];
    const u = {};
    for (const name of names) u[name] = gl.getUniformLocation(program, name);
    return {program, u};
  }

  // x^n as the product of x^(2^i) over n's bits (render::IntegerPowerSource)
  function IntegerPower(name, n) {
    let body = 'float ' + name + '(float x) {\n  float r = 1.0;\n';
    for (let bits = n; bits > 0; bits >>= 1) {
      if (bits & 1) body += '  r *= x;\n';
      if (bits > 1) body += '  x *= x;\n';
    }
    return body + '  return r;\n}\n';
  }
  // levels of detail: [every n-th ring, every n-th side] (render::kDetailLevels)
  const DETAIL = [[1, 1], [2, 1], [4, 1], [2, 2], [4, 2]];
  const WholeExponent = (e) => (e >= 1 && e <= 256 && e === Math.floor(e) ? e : 0);

  const SameCamera = (a, b) => a === b || (a !== null && b !== null &&
      ['view', 'projection'].every((k) => a[k].length === b[k].length && a[k].every((x, i) => x === b[k][i])) &&
      ['light_range', 'spot_inner_deg', 'spot_outer_deg'].every((k) => a[k] === b[k]));

  class Renderer {
    constructor(canvas, scene) {
      this.scene = scene;
      canvas.width = scene.width;
      canvas.height = scene.height;
      // opaque, as a JPEG: a translucent film must not leave the canvas itself see-through
      const gl = canvas.getContext('webgl2', {alpha: false, antialias: false, depth: true,
                                              preserveDrawingBuffer: false});
      if (!gl) throw new Error('this browser has no WebGL2');
      this.gl = gl;
      this.programs = new Map();
      this.statics = scene.meshes.map((m) => {
        const mesh = new Mesh(gl);
        mesh.Upload(m.mesh.positions, m.mesh.normals, m.mesh.texture || null, m.mesh.indices, false);
        return {mesh, material: m.material, faces: m.faces};
      });
      // every program the scene draws, compiled now rather than mid-stream
      for (const m of [scene.materials.intestine, scene.materials.tool, scene.materials.mesentery,
                       ...this.statics.map((st) => st.material)]) this.ProgramFor(m);
      this.ProgramFor(scene.materials.intestine, true);
      this.tube = new Tube(scene.tube);
      this.intestine = new Mesh(gl);
      this.serosa = null;  // the serosa's noises at the intestine's vertices (Serosa)
      this.intestine.Upload(this.tube.positions, this.tube.normals, this.tube.texture, this.tube.indices, true);
      this.tools = new Mesh(gl);
      this.tools_shown = null;  // the tools' triangles in this.tools
      this.film = new Mesh(gl);
      this.point = [0, 0, 0];
      this.intestine_drawn = true;  // false: everything but the intestine (the tests' control)
      // the level of detail's and culling's (Visible): the triangles to draw, the sides of the
      // view each vertex is beyond, per block its first ring, level and nearest depth, the order
      // the blocks are drawn in, the sides each ring keeps
      this.kept = new Uint32Array(this.tube.indices.length);
      this.codes = new Uint8Array(this.tube.positions.length / 3);
      const blocks = Math.ceil((this.tube.rings - 1) / 4);
      this.blocks = new Float64Array(3 * blocks);
      this.order = new Uint32Array(blocks);
      this.ring_step = new Uint8Array(this.tube.rings);
      this.eye = new Float64Array(3);
      this.count = 0;
      // the static picture (wall, organs, targets) for one camera, colour and depth
      // (render::StaticLayer), and the program that copies it into the canvas's
      this.layer = this.Layer(scene.width, scene.height);
      this.layer_camera = null;
      this.copy = Compile(gl, '#version 300 es\n' +
        'void main() { gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0); }\n',
        '#version 300 es\nprecision highp float;\nuniform sampler2D u_colour;\nuniform highp sampler2D u_depth;\n' +
        'out vec4 frag_colour;\nvoid main() {\n  ivec2 p = ivec2(gl_FragCoord.xy);\n' +
        '  frag_colour = texelFetch(u_colour, p, 0);\n  gl_FragDepth = texelFetch(u_depth, p, 0).r;\n}\n');
      gl.useProgram(this.copy.program);
      gl.uniform1i(gl.getUniformLocation(this.copy.program, 'u_colour'), 0);
      gl.uniform1i(gl.getUniformLocation(this.copy.program, 'u_depth'), 1);
      this.empty = gl.createVertexArray();
    }
    // a framebuffer with colour and depth textures (unit 0 and 1)
    Layer(width, height) {
      const gl = this.gl, framebuffer = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
      [[gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, gl.COLOR_ATTACHMENT0],
       [gl.DEPTH_COMPONENT24, gl.DEPTH_COMPONENT, gl.UNSIGNED_INT, gl.DEPTH_ATTACHMENT]].forEach(([inner, format, type, attachment], unit) => {
        const texture = gl.createTexture();
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(gl.TEXTURE_2D, texture);
        gl.texImage2D(gl.TEXTURE_2D, 0, inner, width, height, 0, format, type, null);
        for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
        gl.framebufferTexture2D(gl.FRAMEBUFFER, attachment, gl.TEXTURE_2D, texture, 0);
      });
      gl.activeTexture(gl.TEXTURE0);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      return framebuffer;
    }
    // The program of a material's pattern and exponents, as render::MeshRenderer makes it: the
    // serosa's noises per vertex, the highlights' whole exponents as products. `given`: the
    // serosa's noises come with the vertices (the intestine's, this.serosa); `captured`: the
    // names of the vertex shader's outputs kept by a transform feedback.
    ProgramFor(material, given = false, captured = null) {
      const pattern = material.pattern | 0, per_vertex = pattern === 2;
      const a = WholeExponent(material.shininess), b = WholeExponent(material.sheen_shininess);
      const whole = a > 0 && b > 0, attribute = per_vertex && given;
      const key = pattern + (per_vertex ? 'v' : '') + (attribute ? 'a' : '') + (whole ? ' ' + a + ' ' + b : '') +
                  (captured ? ' ' + captured : '');
      let p = this.programs.get(key);
      if (p !== undefined) return p;
      const sh = this.scene.shaders, version = '#version 300 es\nprecision highp float;\n';
      const define = (per_vertex ? '#define SEROSA_PER_VERTEX 1\n' : '') + (attribute ? '#define SEROSA_ATTRIBUTE 1\n' : '');
      const exponents = whole ? '#define INTEGER_EXPONENTS 1\n' + IntegerPower('PowShininess', a) +
                                IntegerPower('PowSheenShininess', b) : '';
      p = Compile(this.gl, version + define + (per_vertex && !attribute ? sh.noise : '') + sh.vertex,
                  version + '#define PATTERN ' + pattern + '\n' + define + sh.noise + exponents + sh.fragment, captured);
      this.programs.set(key, p);
      return p;
    }
    // The serosa's noises at each vertex of the intestine, by the server's vertex shader run
    // once over its texture points (which never change: the parametric skin's rings keep their
    // radii and places along the bowel) and kept by a transform feedback.
    Serosa() {
      const gl = this.gl, vertices = this.tube.texture.length / 3;
      const p = this.ProgramFor(this.scene.materials.intestine, false, ['v_serosa']);
      this.serosa = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, this.serosa);
      gl.bufferData(gl.ARRAY_BUFFER, 12 * vertices, gl.STATIC_DRAW);
      gl.bindBuffer(gl.ARRAY_BUFFER, null);
      const feedback = gl.createTransformFeedback();
      gl.useProgram(p.program);
      gl.bindVertexArray(this.intestine.vao);
      gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, feedback);
      gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, this.serosa);
      gl.enable(gl.RASTERIZER_DISCARD);
      gl.beginTransformFeedback(gl.POINTS);
      gl.drawArrays(gl.POINTS, 0, vertices);
      gl.endTransformFeedback();
      gl.disable(gl.RASTERIZER_DISCARD);
      gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, null);
      gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, null);
      gl.bindVertexArray(null);
      gl.deleteTransformFeedback(feedback);
      this.intestine.Attribute(this.serosa);
    }
    Use(material, faces, given = false) {
      const gl = this.gl, c = this.scene.camera, p = this.ProgramFor(material, given);
      gl.useProgram(p.program);
      gl.uniformMatrix4fv(p.u.u_view, false, c.view);
      gl.uniformMatrix4fv(p.u.u_projection, false, c.projection);
      gl.uniform3fv(p.u.u_albedo, material.albedo);
      gl.uniform1f(p.u.u_ambient, material.ambient);
      gl.uniform1f(p.u.u_specular, material.specular);
      gl.uniform1f(p.u.u_shininess, material.shininess);
      gl.uniform1f(p.u.u_sheen, material.sheen);
      gl.uniform1f(p.u.u_sheen_shininess, material.sheen_shininess);
      gl.uniform1f(p.u.u_metallic, material.metallic);
      gl.uniform1f(p.u.u_light_range, c.light_range);
      gl.uniform1f(p.u.u_opacity, material.opacity);
      gl.uniform3fv(p.u.u_vessel, material.vessel);
      const cone = c.spot_outer_deg > 0 && c.spot_outer_deg > c.spot_inner_deg, rad = Math.PI / 180;
      gl.uniform2f(p.u.u_spot, cone ? Math.cos(c.spot_inner_deg * rad) : 0, cone ? Math.cos(c.spot_outer_deg * rad) : 1);
      const translucent = material.opacity < 1;
      if (translucent) {
        gl.enable(gl.BLEND);
        // the colour blended, the frame's alpha kept opaque
        gl.blendFuncSeparate(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA, gl.ZERO, gl.ONE);
        gl.depthMask(false);
      } else {
        gl.disable(gl.BLEND);
        gl.depthMask(true);
      }
      if (faces === 'both') {
        gl.disable(gl.CULL_FACE);
      } else {
        gl.enable(gl.CULL_FACE);
        gl.cullFace(faces === 'front' ? gl.BACK : gl.FRONT);
      }
    }
    Clear() {
      const gl = this.gl, b = this.scene.background;
      gl.depthMask(true);
      gl.clearColor(b[0], b[1], b[2], 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    }
    // Draws control points q (flat, 3 per point) and the tools' triangles (or null): a copy of
    // the static picture (drawn again when the camera changed), the intestine, the tools and the
    // mesentery over it, as the server's render::SceneRenderer.
    Draw(q, tools) {
      const gl = this.gl, s = this.scene, m = s.materials;
      gl.viewport(0, 0, s.width, s.height);
      gl.enable(gl.DEPTH_TEST);
      if (!SameCamera(this.layer_camera, s.camera)) {
        gl.bindFramebuffer(gl.FRAMEBUFFER, this.layer);
        this.Clear();
        for (const st of this.statics) {
          this.Use(st.material, st.faces);
          st.mesh.Draw();
        }
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        this.layer_camera = s.camera;
      }
      // one triangle over the canvas writes the layer's colour and depth (a blit into the
      // canvas cost SwiftShader four times as much)
      gl.useProgram(this.copy.program);
      gl.disable(gl.BLEND);
      gl.disable(gl.CULL_FACE);
      gl.depthMask(true);
      gl.depthFunc(gl.ALWAYS);
      gl.bindVertexArray(this.empty);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.depthFunc(gl.LESS);
      if (this.intestine_drawn) {
        this.tube.Build(q);
        if (this.serosa === null) {
          this.intestine.Upload(this.tube.positions, this.tube.normals, this.tube.texture, null, true);
          this.Serosa();
        } else {
          this.intestine.Move(this.tube.positions, this.tube.normals);
        }
        this.intestine.Triangles(this.kept, this.Visible());
        this.Use(m.intestine, 'front', true);
        this.intestine.Draw();
      }
      if (tools !== null) {
        if (tools !== this.tools_shown) this.tools.Upload(tools.positions, tools.normals, null, tools.indices, true);
        this.tools_shown = tools;
        this.Use(m.tool, 'front');
        this.tools.Draw();
      }
      if (s.mesentery) this.DrawFilm(q, s.mesentery);
      gl.disable(gl.BLEND);
      gl.depthMask(true);
    }
    // The intestine's triangles to draw, into this.kept (their count), as the server's
    // render::SkinDetail picks them: the tube cut into blocks of 4 rings; a block wholly beyond
    // one side of the view is left out, the others drawn nearest first, each at the coarsest level
    // of detail (every ring or every 2nd or 4th, every side or every 2nd) whose surface stays within
    // a pixel of the full skin's at the block's nearest depth (positions, and normals' turn times
    // half the cell); the caps at full detail. Of those, the triangles facing away from the eye
    // (by more than a thousandth of edge-on) are left out too: GL would drop them, but
    // SwiftShader only after it has set each one up.
    Visible() {
      const c = this.scene.camera, V = c.view, P = c.projection, tube = this.tube, X = tube.positions;
      const m = tube.sides, K = tube.rings, first = 1 + (tube.cap - 1) * m, codes = this.codes;
      const M = new Float64Array(16);  // P V, column-major
      for (let col = 0; col < 4; ++col) {
        for (let row = 0; row < 4; ++row) {
          let sum = 0;
          for (let k = 0; k < 4; ++k) sum += P[4 * k + row] * V[4 * col + k];
          M[4 * col + row] = sum;
        }
      }
      for (let v = 0, i = 0; i < X.length; ++v, i += 3) {  // which sides of the view each vertex is beyond
        const x = X[i], y = X[i + 1], z = X[i + 2];
        const cx = M[0] * x + M[4] * y + M[8] * z + M[12], cy = M[1] * x + M[5] * y + M[9] * z + M[13];
        const cz = M[2] * x + M[6] * y + M[10] * z + M[14], cw = M[3] * x + M[7] * y + M[11] * z + M[15];
        codes[v] = (cx < -cw) | (cx > cw) << 1 | (cy < -cw) << 2 | (cy > cw) << 3 | (cz < -cw) << 4 | (cz > cw) << 5;
      }
      // the eye (-R^T t of the rigid view), depth in front of it, metres per pixel at depth 1
      this.eye[0] = -(V[0] * V[12] + V[1] * V[13] + V[2] * V[14]);
      this.eye[1] = -(V[4] * V[12] + V[5] * V[13] + V[6] * V[14]);
      this.eye[2] = -(V[8] * V[12] + V[9] * V[13] + V[10] * V[14]);
      const pixel = 2 / (Math.max(1, this.scene.height) * Math.abs(P[5]));
      this.count = 0;
      const I = tube.indices, caps = 3 * (m + 2 * m * (tube.cap - 1));
      for (const [begin, end] of [[0, caps], [I.length - caps, I.length]]) {
        for (let t = begin; t < end; t += 3) this.Keep(I[t], I[t + 1], I[t + 2]);
      }
      const blocks = this.blocks, step = this.ring_step;
      let drawn = 0;
      step.fill(2);
      for (let b = 0, a0 = 0; a0 + 1 < K; ++b, a0 += 4) {
        const a1 = Math.min(a0 + 4, K - 1);
        let outside = 63, near = Infinity, x0 = Infinity, y0 = Infinity, z0 = Infinity;
        let x1 = -Infinity, y1 = -Infinity, z1 = -Infinity;  // the block's bounding box
        for (let v = first + a0 * m, i = 3 * v; v < first + (a1 + 1) * m; ++v, i += 3) {
          outside &= codes[v];
          const x = X[i], y = X[i + 1], z = X[i + 2];
          if (x < x0) x0 = x;
          if (x > x1) x1 = x;
          if (y < y0) y0 = y;
          if (y > y1) y1 = y;
          if (z < z0) z0 = z;
          if (z > z1) z1 = z;
        }
        let level = 4;  // outside: its rings take the sides of the drawn neighbour
        if (outside === 0) {
          // the box's nearest corner's depth, -(view z)
          near = -V[14] - Math.max(V[2] * x0, V[2] * x1) - Math.max(V[6] * y0, V[6] * y1) - Math.max(V[10] * z0, V[10] * z1);
          const allowed = pixel * Math.max(0, near);
          for (level = 4; level > 0; --level) {
            const [stride, sides] = DETAIL[level];
            if (m % sides === 0 && m / sides >= 4 && this.Within(a0, a1, stride, sides, allowed)) break;
          }
          this.order[drawn++] = b;
        }
        blocks[3 * b] = a0;
        blocks[3 * b + 1] = level;
        blocks[3 * b + 2] = near;
        const sides = DETAIL[level][1];
        for (let i = a0; i <= a1; ++i) step[i] = i === a0 || i === a1 ? Math.min(step[i], sides) : sides;
      }
      step[0] = step[K - 1] = 1;
      const order = this.order.subarray(0, drawn).sort((x, y) => blocks[3 * x + 2] - blocks[3 * y + 2]);
      for (const b of order) {
        const a0 = blocks[3 * b], a1 = Math.min(a0 + 4, K - 1), stride = DETAIL[blocks[3 * b + 1]][0];
        for (let a = a0; a < a1; a += stride) {
          const next = Math.min(a + stride, a1);
          this.Strip(first + a * m, step[a], first + next * m, step[next]);
        }
      }
      return this.count;
    }
    // Whether the rings a0..a1 drawn every `stride`-th ring and `sides`-th side stay within
    // `allowed` (m) of the full skin (render::SkinDetail::Within)
    Within(a0, a1, stride, sides, allowed) {
      const tube = this.tube, X = tube.positions, N = tube.normals, m = tube.sides, first = 1 + (tube.cap - 1) * m;
      const allowed2 = allowed * allowed;
      for (let i = a0; i <= a1; ++i) {
        const offset = (i - a0) % stride, i0 = i - offset, i1 = Math.min(i0 + stride, a1);
        const t = i1 > i0 ? (i - i0) / (i1 - i0) : 0, r0 = first + i0 * m, r1 = first + i1 * m;
        for (let j = 0; j < m; ++j) {
          const j0 = j - j % sides;
          if (offset === 0 && j === j0) continue;  // a kept vertex
          const u = (j - j0) / sides, j1 = j0 + sides < m ? j0 + sides : j0 + sides - m;
          const p = 3 * (first + i * m + j), p00 = 3 * (r0 + j0), p01 = 3 * (r0 + j1), p10 = 3 * (r1 + j0), p11 = 3 * (r1 + j1);
          const w00 = (1 - t) * (1 - u), w01 = (1 - t) * u, w10 = t * (1 - u), w11 = t * u;
          const dx = X[p] - (w00 * X[p00] + w01 * X[p01] + w10 * X[p10] + w11 * X[p11]);
          const dy = X[p + 1] - (w00 * X[p00 + 1] + w01 * X[p01 + 1] + w10 * X[p10 + 1] + w11 * X[p11 + 1]);
          const dz = X[p + 2] - (w00 * X[p00 + 2] + w01 * X[p01 + 2] + w10 * X[p10 + 2] + w11 * X[p11 + 2]);
          if (dx * dx + dy * dy + dz * dz > allowed2) return false;
          // the shading's error as a bump of that slope across the coarse cell
          let sx = w00 * N[p00] + w01 * N[p01] + w10 * N[p10] + w11 * N[p11];
          let sy = w00 * N[p00 + 1] + w01 * N[p01 + 1] + w10 * N[p10 + 1] + w11 * N[p11 + 1];
          let sz = w00 * N[p00 + 2] + w01 * N[p01 + 2] + w10 * N[p10 + 2] + w11 * N[p11 + 2];
          const shade = Math.sqrt(sx * sx + sy * sy + sz * sz) || 1;
          sx = N[p] - sx / shade; sy = N[p + 1] - sy / shade; sz = N[p + 2] - sz / shade;
          const ax = X[p10] - X[p00], ay = X[p10 + 1] - X[p00 + 1], az = X[p10 + 2] - X[p00 + 2];
          const bx = X[p01] - X[p00], by = X[p01 + 1] - X[p00 + 1], bz = X[p01 + 2] - X[p00 + 2];
          const cell2 = Math.max(ax * ax + ay * ay + az * az, bx * bx + by * by + bz * bz);
          if (0.25 * (sx * sx + sy * sy + sz * sz) * cell2 > allowed2) return false;
        }
      }
      return true;
    }
    // The triangles joining the ring at vertex a (every step_a-th side) to the ring at b
    // (render::SkinDetail::Strip): with equal steps the skin's own, else around both by angle.
    Strip(a, step_a, b, step_b) {
      const m = this.tube.sides, na = m / step_a, nb = m / step_b;
      if (step_a === step_b) {
        for (let j = 0; j < m; j += step_a) {
          const next = j + step_a < m ? j + step_a : 0;
          this.Keep(a + j, b + next, b + j);
          this.Keep(a + j, a + next, b + next);
        }
        return;
      }
      const A = (k) => a + (k * step_a) % m, B = (k) => b + (k * step_b) % m;
      let ia = 0, ib = 0;
      while (ia < na || ib < nb) {
        if (ib >= nb || (ia < na && (ia + 1) * step_a < (ib + 1) * step_b)) {
          this.Keep(A(ia), A(ia + 1), B(ib));
          ++ia;
        } else {
          this.Keep(A(ia), B(ib + 1), B(ib));
          ++ib;
        }
      }
    }
    // triangle a b d into this.kept unless wholly beyond a side of the view or facing away
    Keep(a, b, d) {
      const codes = this.codes;
      if ((codes[a] & codes[b] & codes[d]) !== 0) return;
      const X = this.tube.positions, e = this.eye, ia = 3 * a, ib = 3 * b, id = 3 * d;
      const ax = X[ia], ay = X[ia + 1], az = X[ia + 2];
      const ux = X[ib] - ax, uy = X[ib + 1] - ay, uz = X[ib + 2] - az;
      const wx = X[id] - ax, wy = X[id + 1] - ay, wz = X[id + 2] - az;
      const nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;  // counter-clockwise: front
      const sx = e[0] - ax, sy = e[1] - ay, sz = e[2] - az, along = nx * sx + ny * sy + nz * sz;
      if (along < 0 && along * along > 1e-6 * (nx * nx + ny * ny + nz * nz) * (sx * sx + sy * sy + sz * sz)) return;
      const kept = this.kept;
      kept[this.count++] = a;
      kept[this.count++] = b;
      kept[this.count++] = d;
    }
    // a ruled film from the root to the centre line, drawn last (translucent)
    DrawFilm(q, film) {
      const s = this.scene, k = film.s.length;
      if (this.film_positions === undefined) {
        this.film_positions = new Float32Array(6 * k);
        this.film_normals = new Float32Array(6 * k);
        this.film_texture = new Float32Array(6 * k);
        const indices = [];
        for (let i = 0; i + 1 < k; ++i) indices.push(2 * i, 2 * i + 2, 2 * i + 3, 2 * i, 2 * i + 3, 2 * i + 1);
        this.film_indices = indices;
      }
      const positions = this.film_positions, normals = this.film_normals, texture = this.film_texture;
      for (let i = 0; i < k; ++i) {
        CurvePoint(q, s.tube.points, film.s[i], this.point);
        positions.set(film.root.slice(3 * i, 3 * i + 3), 6 * i);
        positions.set(this.point, 6 * i + 3);
        const along = s.tube.length * i / (k - 1);
        texture.set([along, 0, 0, along, film.across, 0], 6 * i);
      }
      for (let i = 0; i < k; ++i) {  // across the film: the rung and the root line's direction
        const a = 6 * Math.max(i - 1, 0), b = 6 * Math.min(i + 1, k - 1);
        const rung = sub(positions.slice(6 * i + 3, 6 * i + 6), positions.slice(6 * i, 6 * i + 3));
        const line = sub(positions.slice(b, b + 3), positions.slice(a, a + 3));
        const n = unit(cross(line, rung));
        normals.set(n, 6 * i);
        normals.set(n, 6 * i + 3);
      }
      this.film.Upload(positions, normals, texture, this.film.count === 0 ? this.film_indices : null, true);
      this.Use(s.materials.mesentery, 'both');
      this.film.Draw();
    }
  }

  // ---- the stream: the latest two skeleton messages, drawn between them --------------------
  class Player {
    constructor(canvas, scene, status) {
      this.renderer = new Renderer(canvas, scene);
      this.canvas = canvas;
      this.status = status;
      this.previous = null;  // {points, arrived}
      this.latest = null;
      this.states = 0;       // messages received
      this.drawn = 0;        // frames drawn
      this.changed = 0;      // frames drawn that showed a new state
      this.frame_times = [];
      this.state_times = [];
      this.connected = false;
      this.blend = new Float64Array(3 * scene.tube.points);
      this.shown_step = -1;
    }
    Receive(message) {
      const state = JSON.parse(message);
      state.points = Float64Array.from(state.points);
      state.arrived = performance.now();
      state.age_ms = Date.now() - state.utime / 1000;
      if (this.latest !== null && this.latest.step === state.step) {
        this.latest.arrived_same = state.arrived;  // a paused session: nothing to interpolate
        this.latest.age_ms = state.age_ms;
      } else {
        this.previous = this.latest;
        this.latest = state;
      }
      if (state.camera) this.renderer.scene.camera = state.camera;  // a camera a client set
      ++this.states;
      this.state_times.push(state.arrived);
    }
    // Control points for time `now`: from the previous state to the latest over the interval
    // that separated their arrivals (the picture runs that interval behind the stream).
    Points(now) {
      const a = this.previous, b = this.latest;
      if (a === null || a.points.length !== b.points.length) return b.points;
      const span = Math.max(b.arrived - a.arrived, 1);
      const w = Math.min(Math.max((now - b.arrived) / span, 0), 1);
      for (let i = 0; i < this.blend.length; ++i) this.blend[i] = a.points[i] + w * (b.points[i] - a.points[i]);
      return w >= 1 ? b.points : this.blend;
    }
    Frame(now) {
      if (this.latest === null) return;
      this.renderer.Draw(this.Points(now), this.latest.tools && this.latest.tools.indices.length ? this.latest.tools : null);
      ++this.drawn;
      this.frame_times.push(now);
      const moving = this.previous !== null && now - this.latest.arrived < this.latest.arrived - this.previous.arrived;
      if (moving || this.latest.step !== this.shown_step) ++this.changed;
      this.shown_step = this.latest.step;
    }
    Rates(now) {
      const recent = (times) => { while (times.length && now - times[0] > 2000) times.shift(); return times.length / 2; };
      return {fps: recent(this.frame_times), states_hz: recent(this.state_times)};
    }
  }

  return {Player, Renderer, Tube, CurvePoint};
})();
