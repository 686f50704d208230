void main() {
  for (int i = 0; i < SL; ++i) S[i] = vec4(0.0);
  for (int i = 0; i < TL; ++i) T[i] = vec4(lessThan(ivec4(4 * i) + ivec4(0, 1, 2, 3), ivec4(KT)));
  vec4 white[SL];
  for (int i = 0; i < SL; ++i) white[i] = texelFetch(u_table, ivec2(1 + i, u_entries), 0);

  // Window row y is image row y, so the layers read back in image order (row 0 at the top).
  float u = 2.0 * gl_FragCoord.x / u_image.x - 1.0;
  float v = 1.0 - 2.0 * gl_FragCoord.y / u_image.y;
  vec3 origin = u_eye, dir = u_forward;
  if (u_orthographic != 0) origin += u * u_right + v * u_up;
  else dir = normalize(u_forward + u * u_right + v * u_up);
  vec3 o = origin * u_inv_spacing + u_centre;
  vec3 d = dir * u_inv_spacing;
  float t0 = 0.0, t1 = 3.0e38;
  bool hit = true;
  for (int a = 0; a < 3; ++a) {
    if (abs(d[a]) < 1e-30) {
      hit = hit && o[a] >= 0.0 && o[a] <= u_hi[a];
    } else {
      float ta = -o[a] / d[a], tb = (u_hi[a] - o[a]) / d[a];
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    }
  }
  if (hit && t1 > t0) {
    vec3 view = -dir;
    vec3 light = u_headlight != 0 ? view : u_light;
    vec3 halfway = normalize(light + view);
    float first = t0 + 0.5 * u_step;
    int samples = int(ceil((t1 - first) / u_step));
    int occupied_until = 0;
    for (int i = 0; i < samples;) {
      float t = first + float(i) * u_step;
      vec3 p = o + t * d;
      // Empty space: jump past the largest empty block; in an occupied one, look again only
      // once the ray has left it.
      if (u_skip != 0 && i >= occupied_until) {
        ivec3 c = ivec3(clamp(p, vec3(0.0), u_hi));
        uint empty_shift = texelFetch(u_empty, c >> u_block_shift, 0).r;
        if (empty_shift != 0u) {
          i = firstSamplePast(int(empty_shift), p, d, i, t, first);
          continue;
        }
        occupied_until = firstSamplePast(u_block_shift, p, d, i, t, first);
      }
      vec3 pc = clamp(p, vec3(0.0), u_hi);
#if PRECOMPUTED
      vec4 vg = field(pc) * u_decode_scale + u_decode_offset;
      float value = vg.x;
      vec3 g = vg.yzw;
#else
      float value = field(pc).r;
#endif
      blendRow(pc, value);
      if (acc[0].x > 0.0) {
#if !PRECOMPUTED
        vec3 g;
        for (int a = 0; a < 3; ++a) {
          vec3 step_a = vec3(0.0);
          step_a[a] = 1.0;
          g[a] = (field(clamp(p + step_a, vec3(0.0), u_hi)).r -
                  field(clamp(p - step_a, vec3(0.0), u_hi)).r) * u_half_inv_spacing[a];
        }
#endif
        // Two-sided Phong (classification/classified_sample.h): full light and no highlight where the
        // gradient vanishes.
        float shade = u_ambient + u_diffuse, highlight = 0.0;
        float len = length(g);
        if (len > 1e-6) {
          shade = u_ambient + u_diffuse * abs(dot(g, light) / len);
          float cos_h = min(abs(dot(g, halfway) / len), 1.0);
          if (cos_h > u_highlight_floor) highlight = u_specular * pow(cos_h, u_shininess);
        }
        float hs = highlight * acc[0].y;
        for (int c = 0; c < SL; ++c)
          S[c] += (KT > 1 ? T[c] : vec4(T[0].x)) * (acc[1 + c] * shade + white[c] * hs);
      }
      float tmax = 0.0;
      for (int c = 0; c < TL; ++c) {
        T[c] *= acc[1 + SL + c];
        tmax = max(tmax, max(max(T[c].x, T[c].y), max(T[c].z, T[c].w)));
      }
      if (tmax < u_termination) break;
      ++i;
    }
  }
  for (int j = 0; j < NOUT; ++j) o_layers[j] = FIRST + j < SL ? S[FIRST + j] : T[FIRST + j - SL];
}
