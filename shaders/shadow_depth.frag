#version 450 core
// Depth only: the rasteriser writes gl_FragDepth (with the caller's polygon
// offset); nothing else to do.

void main() {}
