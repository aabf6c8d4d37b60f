#pragma once
/// \file detail/stb.hpp
/// stb_image (decoding) and stb_image_write's zlib compressor, compiled with internal linkage into
/// each translation unit that includes areamatch's I/O headers. That keeps areamatch header-only:
/// users link nothing for images and cannot get duplicate-symbol errors from stb.
/// If your own code also includes stb_image.h, include it *after* areamatch's I/O headers or
/// define its implementation with STB_IMAGE_STATIC as well.

#ifndef AREAMATCH_STB_INCLUDED
#define AREAMATCH_STB_INCLUDED

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO           // areamatch reads files itself, with its own error messages
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

#endif
