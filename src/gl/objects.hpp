#pragma once
// Move-only owners of GL objects (one template, one traits struct per object type). A
// moved-from owner holds 0 and its destructor does nothing; nothing here is copyable, so no
// GL name is ever deleted twice or leaked by a copy. Objects are created with DSA (GL 4.5).
#include "gl/gl.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace pr::gl {

template <typename Traits>
class Object {
public:
    Object() = default;
    explicit Object(GLuint id) : id_(id) {}
    ~Object() { reset(); }
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    Object(Object&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    Object& operator=(Object&& other) noexcept
    {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }

    // A new GL object of this type (for textures and queries, of `target`).
    template <typename... Args>
    static Object create(Args... args) { return Object(Traits::create(args...)); }

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset()
    {
        if (id_) Traits::destroy(id_);
        id_ = 0;
    }

private:
    GLuint id_ = 0;
};

struct BufferTraits {
    static GLuint create() { GLuint i = 0; glCreateBuffers(1, &i); return i; }
    static void destroy(GLuint i) { glDeleteBuffers(1, &i); }
};
struct VertexArrayTraits {
    static GLuint create() { GLuint i = 0; glCreateVertexArrays(1, &i); return i; }
    static void destroy(GLuint i) { glDeleteVertexArrays(1, &i); }
};
struct TextureTraits {
    static GLuint create(GLenum target) { GLuint i = 0; glCreateTextures(target, 1, &i); return i; }
    static void destroy(GLuint i) { glDeleteTextures(1, &i); }
};
struct FramebufferTraits {
    static GLuint create() { GLuint i = 0; glCreateFramebuffers(1, &i); return i; }
    static void destroy(GLuint i) { glDeleteFramebuffers(1, &i); }
};
struct QueryTraits {
    static GLuint create(GLenum target) { GLuint i = 0; glCreateQueries(target, 1, &i); return i; }
    static void destroy(GLuint i) { glDeleteQueries(1, &i); }
};
struct ShaderTraits {
    static GLuint create(GLenum stage) { return glCreateShader(stage); }
    static void destroy(GLuint i) { glDeleteShader(i); }
};
struct ProgramTraits {
    static GLuint create() { return glCreateProgram(); }
    static void destroy(GLuint i) { glDeleteProgram(i); }
};

using Buffer = Object<BufferTraits>;
using VertexArray = Object<VertexArrayTraits>;
using Texture = Object<TextureTraits>;
using Framebuffer = Object<FramebufferTraits>;
using Query = Object<QueryTraits>;
using Shader = Object<ShaderTraits>;
using Program = Object<ProgramTraits>;

// An immutable buffer (no storage flags) holding `data`; an empty vector gets room for one element,
// since GL refuses a zero size.
template <typename T>
Buffer immutable_buffer(const std::vector<T>& data)
{
    Buffer b = Buffer::create();
    glNamedBufferStorage(b.id(), static_cast<GLsizeiptr>(std::max<std::size_t>(data.size(), 1) * sizeof(T)),
                         data.empty() ? nullptr : data.data(), 0);
    return b;
}

// A texture sampled with `min_filter` and `mag_filter`, repeating in s and t.
inline void sample_repeating(const Texture& t, GLint min_filter, GLint mag_filter)
{
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, min_filter);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, mag_filter);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
}

// A map of floats as a 2D texture of level 0 alone (`format`'s channels per texel, row-major),
// sampled with `filter`, repeating.
inline Texture map_texture(GLenum internal_format, int width, int height, GLenum format, const float* texels,
                           GLint filter)
{
    Texture t = Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, internal_format, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.id(), 0, 0, 0, width, height, format, GL_FLOAT, texels);
    sample_repeating(t, filter, filter);
    return t;
}

} // namespace pr::gl
