// Post-illumination in the browser (design.md §5): rgb = M · (S, T) per pixel, one 3 × P matrix per
// frame (the mixed light, brightness and backdrop folded in, linear sRGB), then sRGB encoding.
// WebGL2: the P half-float planes packed four to a layer of one RGBA16F texture array (⌈P/4⌉
// layers), one fragment shader pass specialised to the layer count. The plain JS path (no
// WebGL2, or ?relight=js) runs a loop generated for the plane count, with the sRGB table svr's
// CPU kernel uses (spectral/srgb_table.h). Where WebGL2 is a software rasteriser (SwiftShader,
// llvmpipe) the JS path is the faster one — 800², 7 planes, headless Chromium on 2 cores: about
// 80 relights/s against 40 — and is chosen unless ?relight=webgl2 asks otherwise.
"use strict";

const SRGB_LUT_SIZE = 1 << 14;

function srgbEncode(v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
}

function halfToFloat(h) {
  const s = (h & 0x8000) ? -1 : 1, e = (h >> 10) & 0x1f, f = h & 0x3ff;
  if (e === 0) return s * f * Math.pow(2, -24);
  if (e === 31) return f ? NaN : s * Infinity;
  return s * (1 + f / 1024) * Math.pow(2, e - 15);
}

const VERTEX_SHADER = `#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}`;

// The fragment shader for `layers` layers, unrolled: SwiftShader runs the unrolled form about
// 1.6× faster than a loop over a uniform count.
function fragmentShader(layers) {
  let sum = "";
  for (let j = 0; j < layers; ++j) sum += `  rgb += matrix[${j}] * texelFetch(planes, ivec3(p, ${j}), 0);\n`;
  return `#version 300 es
precision highp float;
precision highp sampler2DArray;
uniform sampler2DArray planes;
uniform mat4x3 matrix[${Math.max(layers, 1)}];
out vec4 color;
float encode(float v) {
  v = clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  ivec3 size = textureSize(planes, 0);
  ivec2 p = ivec2(gl_FragCoord.xy);
  p.y = size.y - 1 - p.y;  // the image's row 0 is at the top
  vec3 rgb = vec3(0.0);
${sum}  color = vec4(encode(rgb.r), encode(rgb.g), encode(rgb.b), 1.0);
}`;
}

// The JS relight loop for P planes: S and T interleaved per pixel, the 3 × P coefficients as
// arguments, one packed RGBA word written per pixel.
function jsRelightLoop(P) {
  const params = [];
  let body = "const s = " + (SRGB_LUT_SIZE - 1) + ";\nfor (let i = 0, j = 0; i < n; ++i, j += " + P + ") {\n";
  for (const c of ["r", "g", "b"]) {
    const terms = [];
    for (let p = 0; p < P; ++p) { params.push(`${c}${p}`); terms.push(`${c}${p} * d[j + ${p}]`); }
    body += `  let ${c} = ${terms.join(" + ") || "0"};\n  ${c} = ${c} > 0 ? (${c} < 1 ? ${c} : 1) : 0;\n`;
  }
  body += "  out[i] = 0xff000000 | (lut[(b * s + 0.5) | 0] << 16) | (lut[(g * s + 0.5) | 0] << 8) | lut[(r * s + 0.5) | 0];\n}";
  return new Function("d", "out", "lut", "n", ...params, body);
}

// A software rasteriser behind WebGL2 (the renderer string names it).
function softwareWebGL(gl) {
  const ext = gl.getExtension("WEBGL_debug_renderer_info");
  const name = ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  return /swiftshader|llvmpipe|softpipe|software/i.test(String(name));
}

class Relighter {
  // canvas: the <canvas>; path: "webgl2", "js", or "auto" (WebGL2 unless it is missing or a
  // software rasteriser).
  constructor(canvas, path) {
    this.canvas = canvas;
    this.frame = null;
    this.gl = null;
    if (path !== "js") {
      // Probe on a canvas of its own: a canvas keeps the first kind of context it is given.
      const probe = document.createElement("canvas").getContext("webgl2");
      this.software = probe ? softwareWebGL(probe) : false;
      if (probe && (path === "webgl2" || !this.software))
        this.gl = canvas.getContext("webgl2", {antialias: false});
    }
    if (this.gl) {
      this.initWebGL();
    } else {
      this.ctx = canvas.getContext("2d");
      this.lut = new Uint8Array(SRGB_LUT_SIZE);
      for (let i = 0; i < SRGB_LUT_SIZE; ++i)
        this.lut[i] = Math.round(Math.min(Math.max(srgbEncode(i / (SRGB_LUT_SIZE - 1)), 0), 1) * 255);
    }
  }

  get kind() { return this.gl ? "WebGL2" : "JS"; }

  initWebGL() {
    const gl = this.gl;
    this.vao = gl.createVertexArray();
    this.texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
    for (const k of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER])
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, k, gl.NEAREST);
    this.programs = new Map();  // by layer count
  }

  program(layers) {
    if (this.programs.has(layers)) return this.programs.get(layers);
    const gl = this.gl;
    const compile = (type, source) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, source);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, VERTEX_SHADER));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fragmentShader(layers)));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    const program = {p, matrix: gl.getUniformLocation(p, "matrix"), planes: gl.getUniformLocation(p, "planes")};
    this.programs.set(layers, program);
    return program;
  }

  // frame: {width, height, planes: P, data: P planes of half floats (Uint16Array) or floats
  // (Float32Array)}
  setFrame(frame) {
    this.frame = frame;
    this.canvas.width = frame.width;
    this.canvas.height = frame.height;
    const n = frame.width * frame.height, P = frame.planes;
    if (this.gl) {
      const gl = this.gl, layers = Math.ceil(P / 4);
      const half = frame.data instanceof Uint16Array;
      const packed = half ? new Uint16Array(n * 4 * layers) : new Float32Array(n * 4 * layers);
      for (let p = 0; p < P; ++p) {
        const src = frame.data.subarray(p * n, (p + 1) * n);
        const base = Math.floor(p / 4) * n * 4, c = p % 4;
        for (let i = 0; i < n; ++i) packed[base + 4 * i + c] = src[i];
      }
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
      gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
      gl.texImage3D(gl.TEXTURE_2D_ARRAY, 0, half ? gl.RGBA16F : gl.RGBA32F, frame.width,
                    frame.height, layers, 0, gl.RGBA, half ? gl.HALF_FLOAT : gl.FLOAT, packed);
      this.layers = layers;
    } else {
      if (!Relighter.halfTable) {
        Relighter.halfTable = new Float32Array(65536);
        for (let h = 0; h < 65536; ++h) Relighter.halfTable[h] = halfToFloat(h);
      }
      const table = Relighter.halfTable, d = new Float32Array(n * P);
      const half = frame.data instanceof Uint16Array;
      for (let p = 0; p < P; ++p) {
        const src = frame.data.subarray(p * n, (p + 1) * n);
        if (half) for (let i = 0, j = p; i < n; ++i, j += P) d[j] = table[src[i]];
        else for (let i = 0, j = p; i < n; ++i, j += P) d[j] = src[i];
      }
      this.interleaved = d;
      if (!this.loops) this.loops = new Map();
      if (!this.loops.has(P)) this.loops.set(P, jsRelightLoop(P));
      this.imageData = this.ctx.createImageData(frame.width, frame.height);
      this.words = new Uint32Array(this.imageData.data.buffer);
    }
  }

  // matrix: 3 rows of P numbers.
  draw(matrix) {
    if (!this.frame) return;
    this.lastMatrix = matrix;
    if (this.gl) this.drawWebGL(matrix); else this.drawJs(matrix);
  }

  drawWebGL(matrix) {
    const gl = this.gl, P = this.frame.planes;
    // mat4x3 is column-major: column c of layer j holds plane 4j + c's three coefficients.
    const m = new Float32Array(this.layers * 12);
    for (let p = 0; p < P; ++p)
      for (let r = 0; r < 3; ++r) m[p * 3 + r] = matrix[r][p];
    const program = this.program(this.layers);
    gl.viewport(0, 0, this.frame.width, this.frame.height);
    gl.useProgram(program.p);
    gl.bindVertexArray(this.vao);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
    gl.uniform1i(program.planes, 0);
    gl.uniformMatrix4x3fv(program.matrix, false, m);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  drawJs(matrix) {
    const n = this.frame.width * this.frame.height, P = this.frame.planes;
    const coefficients = [];
    for (let r = 0; r < 3; ++r) for (let p = 0; p < P; ++p) coefficients.push(Math.fround(matrix[r][p]));
    this.loops.get(P)(this.interleaved, this.words, this.lut, n, ...coefficients);
    this.ctx.putImageData(this.imageData, 0, 0);
    this.lastMatrix = matrix;
  }

  // Waits until the last draw is done (for timing).
  finish() {
    if (this.gl) { const px = new Uint8Array(4); this.gl.readPixels(0, 0, 1, 1, this.gl.RGBA, this.gl.UNSIGNED_BYTE, px); }
  }

  // The canvas as RGB bytes, row 0 at the top.
  pixels() {
    const w = this.canvas.width, h = this.canvas.height, out = new Uint8Array(w * h * 3);
    if (this.gl) {
      // The drawing buffer is not preserved once composited: draw again in this task.
      this.drawWebGL(this.lastMatrix);
      const rgba = new Uint8Array(w * h * 4);
      this.gl.readPixels(0, 0, w, h, this.gl.RGBA, this.gl.UNSIGNED_BYTE, rgba);
      for (let y = 0; y < h; ++y)
        for (let x = 0; x < w; ++x)
          for (let c = 0; c < 3; ++c) out[3 * (y * w + x) + c] = rgba[4 * ((h - 1 - y) * w + x) + c];
    } else {
      const rgba = this.imageData.data;
      for (let i = 0; i < w * h; ++i) for (let c = 0; c < 3; ++c) out[3 * i + c] = rgba[4 * i + c];
    }
    return out;
  }
}
