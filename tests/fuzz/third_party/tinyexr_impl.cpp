// tinyexr's implementation compiled from the system header (libtinyexr-dev)
// with the fuzzers' instrumentation, ZIP through zlib as Debian builds it.
// Only tests/fuzz builds this; everything else links the distribution's
// libtinyexr.
#define TINYEXR_IMPLEMENTATION
#include <tinyexr.h>
