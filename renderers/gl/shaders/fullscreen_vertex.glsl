#version 450 core
// One triangle covering the viewport; a scissor box limits it where a pass needs fewer pixels.
void main() {
  vec2 p = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID & 2) * 2 - 1);
  gl_Position = vec4(p, 0.0, 1.0);
}
