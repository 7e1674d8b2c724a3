// The trainee page's fluoroscopic image in WebGL2: the native FluoroRenderer's shaders
// (host/app/include/app/fluoro_shaders.hpp: one text for GLSL 3.30 and GLSL ES 3.00, handed over
// by the worker from the wasm session), fed by the same inputs, made in the haptic worker by the
// native code compiled to WebAssembly (host/wasm browser_fluoro.hpp: the lumen tied to the flow's contrast cells, the iodine per cell at the pulse, the tools' tubes and
// their mu, the head phantom's projection, the noise and display figures).
//
// Per image (a new pulse, pose or size), as the native renderer:
//   scene pass   each scene (shown; the mask for subtraction; the roadmap and its mask) into a
//                float target, blended additively: every face adds sign * mu * d (entering faces
//                negative), the vessel's mu from the cells' iodine, so a ray sums mu times its
//                path inside; the vessel also sums sign mu, sign d^2 and sign d (the trapezoid
//                correction of mu varying along a chord);
//   composite    the monitor's grey per pixel: the phantom's L plus the scenes', log transmission
//                through the fluoroscopy window with quantum noise (a hash of pixel and pulse),
//                subtraction, or the roadmap over live fluoroscopy; black outside the field;
//   scale        the (binned) image to the canvas, bilinear.
// What differs from the native renderer, for WebGL2: the cells' iodine is a 2D float texture
// (no buffer textures; the shared text's GL_ES branch), the composite reads the phantom as a texture (no framebuffer fetch) over
// the whole image (the native one limits the scene reads to the scenes' 64-pixel cells, a
// saving for software rasterisers), and the float targets need EXT_color_buffer_float and
// EXT_float_blend (the view says so in one line without them).

// FluoroHeader (host/wasm/include/wasm/browser_fluoro.hpp).
export const H = {
  hasImage: 0, pulse: 1, subtracted: 2, roadmap: 3, width: 4, height: 5, lRef: 6, iodineMu: 7, sod: 8, source: 9,
  fieldHalf: 12, sigma: 13, seeds: 17, display: 21, viewProj: 26, sceneVersion: 42, phantomVersion: 43, scenes: 44, size: 56,
};

const CELLS_W = 1024;  // the cells' texture: cell i at (i % CELLS_W, i / CELLS_W)

function compile(gl, vs, fs, what) {
  const program = gl.createProgram();
  for (const [type, source] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error('fluoroscopy ' + what + ' shader: ' + gl.getShaderInfoLog(s));
    gl.attachShader(program, s);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error('fluoroscopy ' + what + ' program: ' + gl.getProgramInfoLog(program));
  const uniforms = {};
  const n = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; ++i) {
    const name = gl.getActiveUniform(program, i).name;
    uniforms[name] = gl.getUniformLocation(program, name);
  }
  return { program, uniforms };
}

function floatTexture(gl, internal, format, w, h, data = null) {
  const t = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, t);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  gl.texImage2D(gl.TEXTURE_2D, 0, internal, w, h, 0, format, internal === gl.RGBA8 ? gl.UNSIGNED_BYTE : gl.FLOAT, data);
  return t;
}

function meshArrays(gl, vertices, indices) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  const vbo = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
  gl.bufferData(gl.ARRAY_BUFFER, vertices, gl.STATIC_DRAW);
  const ebo = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ebo);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
  gl.enableVertexAttribArray(1);
  gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 24, 12);
  gl.bindVertexArray(null);
  return { vao, vbo, ebo, count: indices.length };
}

export class FluoroView {
  // `glsl`: the native renderer's shader texts from the worker (cbx_fluoro_shader: version,
  // sceneVs, sceneFs, fullVs, compositeFs, scaleFs). Throws one line when WebGL2 cannot draw it.
  constructor(canvas, glsl) {
    this.pixelRatio = devicePixelRatio;  // canvas pixels per CSS pixel (the page's ?scale= lowers it)
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: false, depth: false, alpha: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2: no fluoroscopic image');
    for (const ext of ['EXT_color_buffer_float', 'EXT_float_blend']) {
      if (!gl.getExtension(ext)) throw new Error(`this browser's WebGL2 lacks ${ext} (float targets): no fluoroscopic image`);
    }
    this.gl = gl;
    const v = glsl.version;
    this.scene = compile(gl, v + glsl.sceneVs, v + glsl.sceneFs, 'scene');
    this.composite = [0, 1, 2].map((mode) => compile(gl, v + glsl.fullVs, `${v}#define MODE ${mode}\n` + glsl.compositeFs, 'composite'));
    this.scale = compile(gl, v + glsl.fullVs, v + glsl.scaleFs, 'scale');
    this.empty = gl.createVertexArray();
    this.targets = [];  // 4 x {texture, fbo}: shown, mask, roadmap, roadmap mask
    this.cells = null;
    this.vessel = null;
    this.header = null;
    this.drawn = { scene: -1, phantom: -1, width: 0, height: 0 };
    this.stats = { images: 0, last_ms: 0 };
  }

  // The lumen (6 floats a vertex: x, y, z, cell a, cell b, weight; triangle indices), once.
  setVessel(vertices, indices) {
    this.vessel = meshArrays(this.gl, vertices, indices);
  }

  // The worker's image inputs: the header, and the phantom or the scenes when they are new.
  update(f) {
    const gl = this.gl;
    this.header = f.header;
    if (f.phantom) {
      if (this.phantom) gl.deleteTexture(this.phantom);
      this.phantom = floatTexture(gl, gl.RG32F, gl.RG, f.header[H.width], f.header[H.height], f.phantom);
      this.phantomSize = [f.header[H.width], f.header[H.height]];
    }
    if (f.floats) this.sceneData = { floats: f.floats, indices: f.indices, header: f.header.slice() };
  }

  ensureTargets(w, h) {
    const gl = this.gl;
    if (this.targets.length && this.targets.w === w && this.targets.h === h) return;
    for (const t of this.targets) { gl.deleteTexture(t.texture); gl.deleteFramebuffer(t.fbo); }
    const make = (internal, format) => {
      const texture = floatTexture(gl, internal, format, w, h);
      const fbo = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
      return { texture, fbo };
    };
    this.targets = [0, 1, 2, 3].map(() => make(gl.RGBA32F, gl.RGBA));
    this.targets.w = w;
    this.targets.h = h;
    if (this.monitor) { gl.deleteTexture(this.monitor.texture); gl.deleteFramebuffer(this.monitor.fbo); }
    this.monitor = make(gl.RGBA8, gl.RGBA);
    gl.bindTexture(gl.TEXTURE_2D, this.monitor.texture);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  }

  // One scene into target k: the vessel with the scene's iodine, then its tools.
  accumulate(k, at, data, w, h) {
    const gl = this.gl;
    const head = data.header;
    const cells = head[H.scenes + 3 * k];
    const toolFloats = head[H.scenes + 3 * k + 1];
    const toolIndices = head[H.scenes + 3 * k + 2];
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.targets[k].fbo);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    gl.enable(gl.BLEND);
    gl.blendEquation(gl.FUNC_ADD);
    gl.blendFunc(gl.ONE, gl.ONE);
    const s = this.scene;
    gl.useProgram(s.program);
    gl.uniformMatrix4fv(s.uniforms.u_view_proj, false, Float32Array.from(head.subarray(H.viewProj, H.viewProj + 16)));
    gl.uniform4f(s.uniforms.u_source, head[H.source], head[H.source + 1], head[H.source + 2], head[H.sod]);
    gl.uniform1f(s.uniforms.u_iodine_mu, head[H.iodineMu]);
    gl.uniform1i(s.uniforms.u_cells, 5);
    if (cells > 0 && this.vessel && data.floats.subarray(at.f, at.f + cells).some((c) => c > 0)) {
      const rows = Math.ceil(cells / CELLS_W);
      const padded = new Float32Array(rows * CELLS_W);
      padded.set(data.floats.subarray(at.f, at.f + cells));
      if (this.cells) gl.deleteTexture(this.cells);
      gl.activeTexture(gl.TEXTURE5);
      this.cells = floatTexture(gl, gl.R32F, gl.RED, CELLS_W, rows, padded);
      gl.activeTexture(gl.TEXTURE0);
      gl.uniform1f(s.uniforms.u_tool, 0);
      gl.bindVertexArray(this.vessel.vao);
      gl.drawElements(gl.TRIANGLES, this.vessel.count, gl.UNSIGNED_INT, 0);
    }
    at.f += cells;
    if (toolIndices > 0) {
      const tools = meshArrays(gl, data.floats.subarray(at.f, at.f + toolFloats), data.indices.subarray(at.i, at.i + toolIndices));
      gl.uniform1f(s.uniforms.u_tool, 1);
      gl.bindVertexArray(tools.vao);
      gl.drawElements(gl.TRIANGLES, tools.count, gl.UNSIGNED_INT, 0);
      gl.bindVertexArray(null);
      gl.deleteBuffer(tools.vbo);
      gl.deleteBuffer(tools.ebo);
      gl.deleteVertexArray(tools.vao);
    }
    at.f += toolFloats;
    at.i += toolIndices;
    gl.bindVertexArray(null);
    gl.disable(gl.BLEND);
  }

  // The monitor's grey from the phantom and the scenes (the native compose()).
  compose(w, h) {
    const gl = this.gl;
    const head = this.header;
    const mode = head[H.subtracted] ? 2 : head[H.roadmap] ? 1 : 0;
    const c = this.composite[mode];
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.monitor.fbo);
    gl.viewport(0, 0, w, h);
    gl.useProgram(c.program);
    const units = [['u_phantom', this.phantom], ['u_live', this.targets[0].texture], ['u_mask', this.targets[1].texture],
      ['u_road', this.targets[2].texture], ['u_road_mask', this.targets[3].texture]];
    units.forEach(([name, texture], unit) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, texture);
      if (c.uniforms[name]) gl.uniform1i(c.uniforms[name], unit);
    });
    const u = c.uniforms;
    gl.uniform4f(u.u_view, 0, 0, w, h);
    gl.uniform4f(u.u_sigma, ...head.subarray(H.sigma, H.sigma + 4));
    gl.uniform4ui(u.u_seeds, ...head.subarray(H.seeds, H.seeds + 4));
    gl.uniform4f(u.u_display, ...head.subarray(H.display, H.display + 4));
    gl.uniform4f(u.u_mode, 0, 0, 0, head[H.lRef]);
    gl.uniform1f(u.u_anatomy_gain, head[H.display + 4]);
    gl.uniform1f(u.u_field_half, head[H.fieldHalf]);
    gl.bindVertexArray(this.empty);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
    gl.activeTexture(gl.TEXTURE0);
  }

  // Draws when something new is to be shown; true when the canvas shows the monitor (black
  // before the first pulse, as the native trainer's), false before the worker's first inputs.
  render() {
    const gl = this.gl;
    const canvas = this.canvas;
    const cw = Math.max(1, Math.round(canvas.clientWidth * this.pixelRatio));
    const ch = Math.max(1, Math.round(canvas.clientHeight * this.pixelRatio));
    const resized = canvas.width !== cw || canvas.height !== ch;
    if (resized) { canvas.width = cw; canvas.height = ch; }
    const head = this.header;
    const ready = head && head[H.hasImage] && this.phantom && this.sceneData && this.phantomSize[0] === head[H.width] &&
      this.phantomSize[1] === head[H.height] && this.sceneData.header[H.width] === head[H.width];
    if (!ready) {
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, cw, ch);
      gl.clearColor(0, 0, 0, 1);
      gl.clear(gl.COLOR_BUFFER_BIT);
      return !!head;
    }
    const w = head[H.width];
    const h = head[H.height];
    const fresh = this.drawn.scene !== this.sceneData.header[H.sceneVersion] || this.drawn.phantom !== head[H.phantomVersion];
    if (fresh || this.drawn.width !== w || this.drawn.height !== h) {
      const t0 = performance.now();
      this.ensureTargets(w, h);
      gl.disable(gl.DEPTH_TEST);
      gl.disable(gl.CULL_FACE);
      const at = { f: 0, i: 0 };
      const used = [true, !!head[H.subtracted], !!head[H.roadmap], !!head[H.roadmap]];
      for (let k = 0; k < 4; ++k) {
        if (used[k]) this.accumulate(k, at, this.sceneData, w, h);
        else { at.f += this.sceneData.header[H.scenes + 3 * k] + this.sceneData.header[H.scenes + 3 * k + 1]; at.i += this.sceneData.header[H.scenes + 3 * k + 2]; }
      }
      this.compose(w, h);
      this.drawn = { scene: this.sceneData.header[H.sceneVersion], phantom: head[H.phantomVersion], width: w, height: h };
      this.stats.images++;
      this.stats.last_ms = performance.now() - t0;
    } else if (!resized) {
      return true;  // the canvas keeps the image (preserveDrawingBuffer)
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, cw, ch);
    gl.useProgram(this.scale.program);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.monitor.texture);
    gl.uniform1i(this.scale.uniforms.u_image, 0);
    gl.bindVertexArray(this.empty);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
    return true;
  }
}
