#pragma once
/// The one place that includes OpenGL for viscera. Functions come straight from
/// libOSMesa, which exports the whole GL API (core 3.3+ included): no loader, and no
/// libGL, which would hijack the gl* symbols and leave OSMesa's frames black.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
// glext.h needs gl.h's types first: the order is kept by hand.
// clang-format off
#include <GL/osmesa.h>  // includes GL/gl.h
#include <GL/glext.h>
// clang-format on
