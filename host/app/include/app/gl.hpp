#pragma once
// The one include for OpenGL 3.3 core and GLFW in the trainer. Core entry points are taken
// from the system's libGL (GLVND exports them all on Linux), so no loader is needed.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
