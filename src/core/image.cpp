#include "core/image.hpp"
#include "core/error.hpp"
// placeholder: implemented by the image module
