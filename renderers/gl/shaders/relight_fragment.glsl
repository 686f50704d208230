
uniform sampler2DArray u_planes;
uniform float u_matrix[3 * P];
uniform int u_width;
layout(std430, binding = 0) buffer FirstBad { uint first_bad; };
out vec4 o_srgb;
// The sRGB transfer curve (spectral/colorimetry.cpp srgbEncode) on [0, 1].
float encode(float v) {
  v = clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 rgb = vec3(0.0);
  for (int layer = 0; layer * 4 < P; ++layer) {
    vec4 v = texelFetch(u_planes, ivec3(p, layer), 0);
    for (int j = 0; j < 4 && layer * 4 + j < P; ++j) {
      int i = layer * 4 + j;
      rgb += vec3(u_matrix[i], u_matrix[P + i], u_matrix[2 * P + i]) * v[j];
    }
  }
  if (any(isnan(rgb)) || any(isinf(rgb))) atomicMin(first_bad, uint(p.y * u_width + p.x));
  o_srgb = vec4(encode(rgb.r), encode(rgb.g), encode(rgb.b), 1.0);
}
