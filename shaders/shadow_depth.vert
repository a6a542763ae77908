#version 450 core
// Depth of shadow casters as seen from a light (one cube face, a spot's
// face or the sun's orthographic window). Used by the SceneRenderer's
// shadow maps (runtime/src/render/scene_renderer_shadow_maps.cpp).

layout(location = 0) in vec3 a_position;  // world, metres
layout(location = 0) uniform mat4 u_clip_from_world;

void main() { gl_Position = u_clip_from_world * vec4(a_position, 1.0); }
