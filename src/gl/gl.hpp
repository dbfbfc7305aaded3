#pragma once
// The one include for GL calls: glad's loader (entry points fetched through the context
// backend's GetProcAddress). Never include <GL/gl.h> next to it.
#include <glad/gl.h>
