#version 450 core
// svit-walk's statistics overlay: one colour per draw (display sRGB, the
// target already holds tone-mapped display values), blended by its alpha.

layout(location = 0) out vec4 o_colour;

layout(location = 1) uniform vec4 u_colour;

void main() { o_colour = u_colour; }
