// tinygltf's implementation compiled from the system header
// (libtinygltf-dev) with the fuzzers' instrumentation, so coverage and the
// sanitizers reach inside the glTF/GLB parser. Only tests/fuzz builds this;
// everything else links the distribution's libtinygltf. Images are decoded
// by svit's own callback (gltf_loader.cpp), stb_image from libstb.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
