
uniform sampler2DArray u_sheet_buffer;  // quantity q in layer q / 4, component q % 4
float quantity(int q) {
  return texelFetch(u_sheet_buffer, ivec3(ivec2(gl_FragCoord.xy), q / 4), 0)[q % 4];
}
