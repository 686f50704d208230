// Post-illumination in the browser (DESIGN §5): rgb = M · (S, T) per pixel, one 3 × P matrix per
// frame (the mixed light, brightness and backdrop folded in, linear sRGB), then sRGB encoding.
// WebGL2: the P half-float planes packed four to a layer of one RGBA16F texture array (⌈P/4⌉
// layers), one fragment shader pass. Without WebGL2, the same sum in plain JS with the sRGB
// table svr's CPU kernel uses (spectral/srgb_table.h).
"use strict";

const SRGB_LUT_SIZE = 1 << 14;
const MAX_LAYERS = 8;  // 32 planes: ViewSession::kMaxPlanes

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

const FRAGMENT_SHADER = `#version 300 es
precision highp float;
precision highp sampler2DArray;
uniform sampler2DArray planes;
uniform int layers;
uniform mat4x3 matrix[${MAX_LAYERS}];
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
  for (int j = 0; j < ${MAX_LAYERS}; ++j) {
    if (j >= layers) break;
    rgb += matrix[j] * texelFetch(planes, ivec3(p, j), 0);
  }
  color = vec4(encode(rgb.r), encode(rgb.g), encode(rgb.b), 1.0);
}`;

class Relighter {
  // canvas: the <canvas>; useWebGL: false forces the plain JS path.
  constructor(canvas, useWebGL) {
    this.canvas = canvas;
    this.frame = null;
    this.gl = useWebGL ? canvas.getContext("webgl2", {preserveDrawingBuffer: true, antialias: false}) : null;
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
    const compile = (type, source) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, source);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, VERTEX_SHADER));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    this.program = p;
    this.vao = gl.createVertexArray();
    this.texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
    for (const k of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER])
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, k, gl.NEAREST);
    this.uLayers = gl.getUniformLocation(p, "layers");
    this.uMatrix = gl.getUniformLocation(p, "matrix");
    this.uPlanes = gl.getUniformLocation(p, "planes");
  }

  // frame: {width, height, planes: P, data: Uint16Array of P planes of half floats}
  setFrame(frame) {
    this.frame = frame;
    this.canvas.width = frame.width;
    this.canvas.height = frame.height;
    const n = frame.width * frame.height, P = frame.planes;
    if (this.gl) {
      const gl = this.gl, layers = Math.ceil(P / 4);
      const packed = new Uint16Array(n * 4 * layers);
      for (let p = 0; p < P; ++p) {
        const src = frame.data.subarray(p * n, (p + 1) * n);
        const base = Math.floor(p / 4) * n * 4, c = p % 4;
        for (let i = 0; i < n; ++i) packed[base + 4 * i + c] = src[i];
      }
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
      gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
      gl.texImage3D(gl.TEXTURE_2D_ARRAY, 0, gl.RGBA16F, frame.width, frame.height, layers, 0,
                    gl.RGBA, gl.HALF_FLOAT, packed);
      this.layers = layers;
    } else {
      const table = new Float32Array(65536);
      for (let h = 0; h < 65536; ++h) table[h] = halfToFloat(h);
      this.planes = [];
      for (let p = 0; p < P; ++p) {
        const f = new Float32Array(n), src = frame.data.subarray(p * n, (p + 1) * n);
        for (let i = 0; i < n; ++i) f[i] = table[src[i]];
        this.planes.push(f);
      }
      this.imageData = this.ctx.createImageData(frame.width, frame.height);
    }
  }

  // matrix: 3 rows of P numbers.
  draw(matrix) {
    if (!this.frame) return;
    if (this.gl) this.drawWebGL(matrix); else this.drawJs(matrix);
  }

  drawWebGL(matrix) {
    const gl = this.gl, P = this.frame.planes;
    // mat4x3 is column-major: column c of layer j holds plane 4j + c's three coefficients.
    const m = new Float32Array(MAX_LAYERS * 12);
    for (let p = 0; p < P; ++p)
      for (let r = 0; r < 3; ++r) m[p * 3 + r] = matrix[r][p];
    gl.viewport(0, 0, this.frame.width, this.frame.height);
    gl.useProgram(this.program);
    gl.bindVertexArray(this.vao);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.texture);
    gl.uniform1i(this.uPlanes, 0);
    gl.uniform1i(this.uLayers, this.layers);
    gl.uniformMatrix4x3fv(this.uMatrix, false, m);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  drawJs(matrix) {
    const n = this.frame.width * this.frame.height, P = this.frame.planes, out = this.imageData.data;
    const scale = SRGB_LUT_SIZE - 1, lut = this.lut;
    const acc = [new Float32Array(n), new Float32Array(n), new Float32Array(n)];
    for (let r = 0; r < 3; ++r) {
      const a = acc[r];
      for (let p = 0; p < P; ++p) {
        const c = Math.fround(matrix[r][p]), plane = this.planes[p];
        if (c === 0) continue;
        for (let i = 0; i < n; ++i) a[i] += c * plane[i];
      }
    }
    for (let i = 0; i < n; ++i) {
      for (let r = 0; r < 3; ++r) {
        const v = Math.min(Math.max(acc[r][i], 0), 1);
        out[4 * i + r] = lut[Math.floor(v * scale + 0.5)];
      }
      out[4 * i + 3] = 255;
    }
    this.ctx.putImageData(this.imageData, 0, 0);
  }

  // Waits until the last draw is done (for timing).
  finish() {
    if (this.gl) { const px = new Uint8Array(4); this.gl.readPixels(0, 0, 1, 1, this.gl.RGBA, this.gl.UNSIGNED_BYTE, px); }
  }

  // The canvas as RGB bytes, row 0 at the top.
  pixels() {
    const w = this.canvas.width, h = this.canvas.height, out = new Uint8Array(w * h * 3);
    if (this.gl) {
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
