/* gles3-probe: draws one GL ES 3.0 feature per scene into a 64x64 X11 window from an ES 3
 * context, so that a capture of it (apitrace trace --api egl) can be replayed by tiler and by
 * llvmpipe. Build: gcc -O1 -o probe3 probe3.c -lEGL -lGLESv2 -lX11. Run: ./probe3 SCENE. */
#include <EGL/egl.h>
#include <GLES3/gl3.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 64
#define H 64

static EGLDisplay dpy;
static EGLSurface surf;
static EGLConfig config;
static EGLContext ctx;

static void die(const char *what) {
    fprintf(stderr, "probe3: %s\n", what);
    exit(1);
}

static void setup(void) {
    Display *x = XOpenDisplay(NULL);
    if (!x) die("no X display");
    Window win = XCreateSimpleWindow(x, DefaultRootWindow(x), 0, 0, W, H, 0, 0, 0);
    XMapWindow(x, win);
    XFlush(x);
    dpy = eglGetDisplay((EGLNativeDisplayType)x);
    if (!eglInitialize(dpy, NULL, NULL)) die("eglInitialize");
    EGLint attribs[] = {EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                        EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                        EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_NONE};
    EGLint n;
    if (!eglChooseConfig(dpy, attribs, &config, 1, &n) || n != 1) die("eglChooseConfig");
    surf = eglCreateWindowSurface(dpy, config, (EGLNativeWindowType)win, NULL);
    if (surf == EGL_NO_SURFACE) die("eglCreateWindowSurface");
    EGLint ctx_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE};
    ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attribs);
    if (ctx == EGL_NO_CONTEXT) die("eglCreateContext");
    if (!eglMakeCurrent(dpy, surf, surf, ctx)) die("eglMakeCurrent");
    glViewport(0, 0, W, H);
}

static GLuint shader(GLenum kind, const char *source) {
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, NULL);
    glCompileShader(s);
    GLint ok;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "%s\n", log);
        die("compile");
    }
    return s;
}

/* A program; attributes "position" at 0 and "color" at 1 unless the shader places them. */
static GLuint program(const char *vs, const char *fs) {
    GLuint p = glCreateProgram();
    GLuint v = shader(GL_VERTEX_SHADER, vs), f = shader(GL_FRAGMENT_SHADER, fs);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glBindAttribLocation(p, 0, "position");
    glBindAttribLocation(p, 1, "color");
    glLinkProgram(p);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        fprintf(stderr, "%s\n", log);
        die("link");
    }
    glDeleteShader(v);
    glDeleteShader(f);
    return p;
}

static GLuint buffer(GLenum target, GLsizeiptr size, const void *data) {
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, size, data, GL_STATIC_DRAW);
    return b;
}

static const char *color_vs =
    "attribute vec2 position;\nattribute vec4 color;\nvarying vec4 v_color;\n"
    "void main() { v_color = color; gl_Position = vec4(position, 0.0, 1.0); }\n";
static const char *color_fs =
    "precision mediump float;\nvarying vec4 v_color;\nvoid main() { gl_FragColor = v_color; }\n";

/* Vertex array objects: two arrays set up once (interleaved position + colour in one
 * buffer and indices; separate buffers with unsigned-byte colours), drawn alternately;
 * the default array with client-side arrays in between keeps its own state. */
static void scene_vao(void) {
    GLuint p = program(color_vs, color_fs);
    glUseProgram(p);
    GLuint vao[2];
    glGenVertexArrays(2, vao);

    const float quad[] = {-0.9f, -0.9f, 1, 0, 0, 1, -0.1f, -0.9f, 0, 1, 0, 1,
                          -0.9f, -0.1f, 0, 0, 1, 1, -0.1f, -0.1f, 1, 1, 0, 1};
    const GLushort quad_indices[] = {0, 1, 2, 2, 1, 3};
    glBindVertexArray(vao[0]);
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof quad_indices, quad_indices);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(2 * sizeof(float)));

    const float tri[] = {0.1f, 0.1f, 0.9f, 0.1f, 0.5f, 0.9f};
    const GLubyte tri_colors[] = {255, 128, 0, 255, 0, 255, 128, 255, 128, 0, 255, 255};
    glBindVertexArray(vao[1]);
    buffer(GL_ARRAY_BUFFER, sizeof tri, tri);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    buffer(GL_ARRAY_BUFFER, sizeof tri_colors, tri_colors);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, (void *)0);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    glClearColor(0.2f, 0.2f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindVertexArray(vao[0]);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, (void *)0);
    /* The default array: client memory, a constant colour from a disabled attribute. */
    glBindVertexArray(0);
    const float strip[] = {0.1f, -0.9f, 0.9f, -0.9f, 0.1f, -0.1f, 0.9f, -0.1f};
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, strip);
    glDisableVertexAttribArray(1);
    glVertexAttrib4f(1, 0.9f, 0.9f, 0.2f, 1);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(vao[1]);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    /* Array 0 again: attribute 0 is still the client array, attribute 1 still disabled. */
    glBindVertexArray(0);
    const float small[] = {-0.9f, 0.1f, -0.1f, 0.1f, -0.5f, 0.9f};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, small);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDeleteVertexArrays(2, vao);
    eglSwapBuffers(dpy, surf);
}

/* Instancing: a quad drawn 12 times with per-instance offsets (divisor 1) and colours
 * (divisor 2), gl_InstanceID scaling each; then indexed instances through
 * glDrawElementsInstanced. */
static void scene_instanced(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(location = 1) in vec4 color;\n"
        "layout(location = 2) in vec2 offset;\n"
        "out vec4 v_color;\n"
        "void main() {\n"
        "  float s = 1.0 - float(gl_InstanceID) * 0.05;\n"
        "  v_color = color;\n"
        "  gl_Position = vec4(position * s + offset, 0.0, 1.0);\n"
        "}\n",
        "#version 300 es\nprecision mediump float;\nin vec4 v_color;\nout vec4 frag;\n"
        "void main() { frag = v_color; }\n");
    glUseProgram(p);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-0.1f, -0.1f, 0.1f, -0.1f, -0.1f, 0.1f, 0.1f, 0.1f};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    float offsets[12 * 2];
    for (int i = 0; i < 12; i++) {
        offsets[2 * i] = -0.75f + (i % 4) * 0.5f;
        offsets[2 * i + 1] = -0.75f + (i / 4) * 0.5f;
    }
    buffer(GL_ARRAY_BUFFER, sizeof offsets, offsets);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glVertexAttribDivisor(2, 1);
    const GLubyte colors[] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255,
                              255, 255, 0, 255, 0, 255, 255, 255, 255, 0, 255, 255};
    buffer(GL_ARRAY_BUFFER, sizeof colors, colors);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, (void *)0);
    glVertexAttribDivisor(1, 2);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, 12);
    /* Indexed: the top row again, smaller, from the fourth offset on. */
    const GLushort indices[] = {0, 1, 2, 2, 1, 3};
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    const float top[] = {-0.75f, 0.85f, -0.25f, 0.85f, 0.25f, 0.85f, 0.75f, 0.85f};
    GLuint top_buffer = buffer(GL_ARRAY_BUFFER, sizeof top, top);
    glBindBuffer(GL_ARRAY_BUFFER, top_buffer);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glVertexAttribDivisor(1, 1);
    glDrawElementsInstanced(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, (void *)0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Uniform blocks: a std140 block read by the vertex shader (a matrix, a float and a vec2,
 * bound at 2 by range from an offset into a bigger buffer) and one with an instance name
 * read by the fragment shader (an array of vec4 and an int, bound at 5 by base); the
 * buffers change between draws. */
static void scene_ubo(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(std140) uniform Transform {\n"
        "  mat4 m;\n"
        "  float scale;\n"
        "  vec2 shift;\n"
        "};\n"
        "void main() { gl_Position = m * vec4(position * scale + shift, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "uniform Palette {\n"
        "  vec4 colors[3];\n"
        "  int pick;\n"
        "} palette;\n"
        "out vec4 color;\n"
        "void main() { color = palette.colors[palette.pick] * 0.5 + palette.colors[0] * 0.5; }\n");
    glUseProgram(p);
    GLuint transform_index = glGetUniformBlockIndex(p, "Transform");
    GLuint palette_index = glGetUniformBlockIndex(p, "Palette");
    glUniformBlockBinding(p, transform_index, 2);
    glUniformBlockBinding(p, palette_index, 5);

    /* Transform at byte 256 of a 512-byte buffer: m (64), scale at 64, shift at 72. */
    float transform[128] = {0};
    float *t = transform + 64;
    t[0] = 1; t[5] = -1; t[10] = 1; t[15] = 1; /* flip y */
    t[16] = 0.5f;
    t[18] = -0.4f; t[19] = 0.3f;
    GLuint tb = buffer(GL_UNIFORM_BUFFER, sizeof transform, transform);
    glBindBufferRange(GL_UNIFORM_BUFFER, 2, tb, 256, 80);
    /* Palette: colors[3] at 0, 16, 32; pick at 48. */
    float palette[16] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 0};
    int pick = 2;
    memcpy(&palette[12], &pick, 4);
    GLuint pb = buffer(GL_UNIFORM_BUFFER, sizeof palette, palette);
    glBindBufferBase(GL_UNIFORM_BUFFER, 5, pb);

    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glClearColor(0.1f, 0.1f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    /* Change both blocks' data and draw again elsewhere. */
    const float shift[2] = {0.45f, -0.35f};
    glBindBuffer(GL_UNIFORM_BUFFER, tb);
    glBufferSubData(GL_UNIFORM_BUFFER, 256 + 72, sizeof shift, shift);
    const float scale = 0.3f;
    glBufferSubData(GL_UNIFORM_BUFFER, 256 + 64, sizeof scale, &scale);
    pick = 1;
    glBindBuffer(GL_UNIFORM_BUFFER, pb);
    glBufferSubData(GL_UNIFORM_BUFFER, 48, 4, &pick);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* GLSL ES 3.00: positions from gl_VertexID (no attributes), texture() and textureLod() on
 * a mip-mapped texture, outputs at a layout location. */
static void scene_glsl3(void) {
    GLuint p = program(
        "#version 300 es\n"
        "out vec2 uv;\n"
        "void main() {\n"
        "  float id = float(gl_VertexID);\n"
        "  vec2 corner = vec2(mod(id, 2.0), floor(id / 2.0));\n"
        "  uv = corner * 1.5;\n"
        "  gl_Position = vec4(corner * 1.8 - 0.9, 0.0, 1.0);\n"
        "}\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D tex;\n"
        "layout(location = 0) out vec4 color;\n"
        "void main() {\n"
        "  vec4 a = texture(tex, uv);\n"
        "  vec4 b = textureLod(tex, uv, 2.0);\n"
        "  color = uv.x < 0.75 ? a : b;\n"
        "}\n");
    glUseProgram(p);
    unsigned char texels[16 * 16 * 4];
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            unsigned char *c = texels + (y * 16 + x) * 4;
            int on = ((x / 2) ^ (y / 2)) & 1;
            c[0] = on ? 250 : 20;
            c[1] = (unsigned char)(x * 16);
            c[2] = (unsigned char)(y * 16);
            c[3] = 255;
        }
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Immutable storage, sampler objects, buffer copies: an 8x8 texture with 4 levels from
 * glTexStorage2D, each level a colour given by glTexSubImage2D; its own parameters say
 * linear, clamped; a sampler object bound to unit 0 says nearest-mipmap-nearest, repeated,
 * for the left quad and is unbound for the right one. The quads' vertices reach their buffer
 * through glCopyBufferSubData from a staging buffer. */
static void scene_objects(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec4 vertex;\n"
        "out vec2 uv;\n"
        "void main() { uv = vertex.zw; gl_Position = vec4(vertex.xy, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D tex;\n"
        "out vec4 color;\n"
        "void main() { color = texture(tex, uv); }\n");
    glUseProgram(p);
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 4, GL_RGBA8, 8, 8);
    const unsigned char level_colors[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
    unsigned char texels[8 * 8 * 4];
    for (int level = 0; level < 4; level++) {
        int size = 8 >> level;
        for (int i = 0; i < size * size; i++) {
            memcpy(texels + i * 4, level_colors[level], 4);
            if (level == 0 && ((i % 8) / 2 + i / 16) % 2) texels[i * 4 + 2] = 200; /* a checker on level 0 */
        }
        glTexSubImage2D(GL_TEXTURE_2D, level, 0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    GLuint sampler;
    glGenSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_MIRRORED_REPEAT);

    /* Two strips: x, y, s, t; the left one minifies (uv to 6), the right one magnifies. */
    const float strips[] = {-0.95f, -0.9f, 0, 0, -0.05f, -0.9f, 6, 0, -0.95f, 0.9f, 0, 6, -0.05f, 0.9f, 6, 6,
                            0.05f, -0.9f, -0.2f, -0.2f, 0.95f, -0.9f, 1.2f, -0.2f, 0.05f, 0.9f, -0.2f, 1.2f,
                            0.95f, 0.9f, 1.2f, 1.2f};
    GLuint staging = buffer(GL_COPY_READ_BUFFER, sizeof strips, strips);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    GLuint vertices = buffer(GL_ARRAY_BUFFER, sizeof strips + 64, NULL);
    glBindBuffer(GL_COPY_WRITE_BUFFER, vertices);
    glBindBuffer(GL_COPY_READ_BUFFER, staging);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 64, sizeof strips);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, (void *)64);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindSampler(0, sampler);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindSampler(0, 0);
    glDrawArrays(GL_TRIANGLE_STRIP, 4, 4);
    glDeleteSamplers(1, &sampler);
    eglSwapBuffers(dpy, surf);
}

/* Multiple render targets: one draw writes two outputs into two colour textures of a
 * framebuffer (glDrawBuffers), then the window shows the first on the left and the second
 * on the right. */
static void scene_mrt(void) {
    GLuint write = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "out vec2 p;\n"
        "void main() { p = position; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 p;\n"
        "layout(location = 0) out vec4 first;\n"
        "layout(location = 1) out vec4 second;\n"
        "void main() {\n"
        "  first = vec4(p * 0.5 + 0.5, 0.2, 1.0);\n"
        "  second = vec4(0.9, 0.5 - p.x * 0.5, p.y * p.y, 1.0);\n"
        "}\n");
    GLuint show = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "out vec2 uv;\n"
        "void main() { uv = position * 0.5 + 0.5; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D first;\n"
        "uniform sampler2D second;\n"
        "out vec4 color;\n"
        "void main() { color = uv.x < 0.5 ? texture(first, uv) : texture(second, uv); }\n");
    GLuint tex[2];
    glGenTextures(2, tex);
    for (int i = 0; i < 2; i++) {
        glActiveTexture(GL_TEXTURE0 + i);
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, W, H, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[1], 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("framebuffer");
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glViewport(0, 0, W, H);
    glUseProgram(write);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(show);
    glUniform1i(glGetUniformLocation(show, "first"), 0);
    glUniform1i(glGetUniformLocation(show, "second"), 1);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}


/* A full-window quad program that shows texture unit 0 (uv from the position). */
static const char *show_vs =
    "#version 300 es\n"
    "layout(location = 0) in vec2 position;\n"
    "out vec2 uv;\n"
    "void main() { uv = position * 0.5 + 0.5; gl_Position = vec4(position, 0.0, 1.0); }\n";

static GLuint quad_vao(void) {
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quad, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    return vao;
}

static GLuint gradient_program(void) {
    return program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "out vec2 p;\n"
        "void main() { p = position; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 p;\n"
        "out vec4 color;\n"
        "void main() { color = vec4(p * 0.5 + 0.5, fract(p.x * p.y * 3.0), 1.0); }\n");
}

static void draw_triangle(void) {
    const float tri[] = {-0.8f, -0.9f, 0.9f, -0.6f, -0.3f, 0.85f};
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    buffer(GL_ARRAY_BUFFER, sizeof tri, tri);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

/* glBlitFramebuffer: a 32x32 texture framebuffer blitted to the window's bottom-left quarter
 * at 1:1, magnified 2x with NEAREST to the bottom-right, mirrored to the top-left; a 4-sample
 * renderbuffer resolved by a blit into a texture shown in the top-right. */
static void scene_blit(void) {
    GLuint p = gradient_program();
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 32, 32);
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glViewport(0, 0, 32, 32);
    glClearColor(0.1f, 0.1f, 0.4f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glUseProgram(p);
    draw_triangle();

    GLuint ms_rb;
    glGenRenderbuffers(1, &ms_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, ms_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, 32, 32);
    GLuint ms_fb;
    glGenFramebuffers(1, &ms_fb);
    glBindFramebuffer(GL_FRAMEBUFFER, ms_fb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_rb);
    glClearColor(0.4f, 0.1f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    draw_triangle();
    GLuint resolved;
    glGenTextures(1, &resolved);
    glBindTexture(GL_TEXTURE_2D, resolved);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 32, 32);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    GLuint resolve_fb;
    glGenFramebuffers(1, &resolve_fb);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fb);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, resolved, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, ms_fb);
    glBlitFramebuffer(0, 0, 32, 32, 0, 0, 32, 32, GL_COLOR_BUFFER_BIT, GL_NEAREST);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
    glBlitFramebuffer(0, 0, 32, 32, 0, 0, 32, 32, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBlitFramebuffer(0, 0, 16, 16, 32, 0, 64, 32, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBlitFramebuffer(0, 0, 32, 32, 32, 32, 0, 64, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    /* the resolved texture, drawn in the top-right quarter */
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform sampler2D tex;\nout vec4 color;\n"
        "void main() { color = texture(tex, uv); }\n");
    glUseProgram(show);
    glBindTexture(GL_TEXTURE_2D, resolved);
    quad_vao();
    glViewport(32, 32, 32, 32);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* glInvalidateFramebuffer: a framebuffer's depth invalidated after its draws (its colour is then
 * sampled), the window's depth and stencil invalidated before the swap. */
static void scene_invalidate(void) {
    GLuint p = gradient_program();
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, W, H, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    GLuint depth;
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, W, H);
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    glEnable(GL_DEPTH_TEST);
    glClearColor(0.2f, 0.3f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(p);
    draw_triangle();
    const GLenum depth_only[] = {GL_DEPTH_ATTACHMENT};
    glInvalidateFramebuffer(GL_FRAMEBUFFER, 1, depth_only);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_DEPTH_TEST);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform sampler2D tex;\nout vec4 color;\n"
        "void main() { color = texture(tex, uv).bgra; }\n");
    glUseProgram(show);
    quad_vao();
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    const GLenum window_ds[] = {GL_DEPTH, GL_STENCIL};
    glInvalidateFramebuffer(GL_FRAMEBUFFER, 2, window_ds);
    eglSwapBuffers(dpy, surf);
}

/* Depth textures with compare mode: a slanted quad's depth rendered into a DEPTH_COMPONENT24
 * texture, then sampled through sampler2DShadow (LEQUAL against a reference that sweeps
 * across the window), nearest on the left, linear (percentage-closer) on the right, and
 * through textureProj. */
/* The shadow scenes' depth map: a slanted quad and a small triangle in front of it rendered by
 * a depth-only pass into a 32x32 DEPTH_COMPONENT24 texture (nearest, clamped, LEQUAL compare),
 * left bound to unit 0. */
static GLuint render_shadow_map(void) {
    GLuint depth_tex;
    glGenTextures(1, &depth_tex);
    glBindTexture(GL_TEXTURE_2D, depth_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, 32, 32, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_tex, 0);
    glDrawBuffers(0, NULL);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("depth framebuffer");
    GLuint depth_only = program(
        "#version 300 es\nlayout(location = 0) in vec3 position;\n"
        "void main() { gl_Position = vec4(position, 1.0); }\n",
        "#version 300 es\nprecision mediump float;\nvoid main() {}\n");
    glUseProgram(depth_only);
    glViewport(0, 0, 32, 32);
    glEnable(GL_DEPTH_TEST);
    glClearDepthf(1.0f);
    glClear(GL_DEPTH_BUFFER_BIT);
    const float slanted[] = {-1, -1, -0.9f, 1, -1, 0.2f, -1, 1, 0.2f, 1, 1, 0.9f};
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    buffer(GL_ARRAY_BUFFER, sizeof slanted, slanted);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (void *)0);
    const float small[] = {-0.5f, -0.5f, -1.0f, 0.2f, -0.5f, -1.0f, -0.5f, 0.2f, -1.0f};
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    GLuint vao2;
    glGenVertexArrays(1, &vao2);
    glBindVertexArray(vao2);
    buffer(GL_ARRAY_BUFFER, sizeof small, small);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_DEPTH_TEST);

    return depth_tex;
}

static void scene_shadow(void) {
    render_shadow_map();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nprecision mediump sampler2DShadow;\n"
        "in vec2 uv;\nuniform sampler2DShadow shadow;\nuniform float bias;\nout vec4 color;\n"
        "void main() {\n"
        "  float reference = uv.y * 0.8 + 0.1 + bias;\n"
        "  float lit = texture(shadow, vec3(uv * 1.2 - 0.1, reference));\n"
        "  float projected = textureProj(shadow, vec4(uv * 2.0, reference * 2.0, 2.0));\n"
        "  color = vec4(lit, projected, 0.3, 1.0);\n"
        "}\n");
    glUseProgram(show);
    glUniform1f(glGetUniformLocation(show, "bias"), 0.0f);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glScissor(32, 0, 32, 64);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_SCISSOR_TEST);
    eglSwapBuffers(dpy, surf);
}

/* A sampler object's depth comparison: textureLod and textureProj on the shadow map, the left
 * half with the texture's own LEQUAL nearest compare, the right half through a sampler object
 * comparing GREATER with linear filtering. (llvmpipe's ES 3 context does not expose
 * GL_EXT_shadow_samplers, so shadow2DEXT is tested in tiler-glsl only.) */
static void scene_shadow_sampler(void) {
    render_shadow_map();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nprecision mediump sampler2DShadow;\n"
        "in vec2 uv;\nuniform sampler2DShadow shadow;\nout vec4 color;\n"
        "void main() {\n"
        "  float reference = 0.9 - uv.x * 0.7;\n"
        "  float lit = textureLod(shadow, vec3(uv.yx, reference), 0.0);\n"
        "  float projected = textureProj(shadow, vec4(uv * 3.0, reference * 3.0, 3.0));\n"
        "  color = vec4(lit, projected, 0.6, 1.0);\n"
        "}\n");
    glUseProgram(show);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    GLuint sampler;
    glGenSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_FUNC, GL_GREATER);
    glBindSampler(0, sampler);
    glScissor(32, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_SCISSOR_TEST);
    eglSwapBuffers(dpy, surf);
}

/* GL_RGB10_A2 textures of UNSIGNED_INT_2_10_10_10_REV texels: one by glTexImage2D with data
 * (left half), one by glTexStorage2D then glTexSubImage2D (right half), both linear. */
static void scene_rgb10a2(void) {
    GLuint texels[8 * 8];
    for (int y = 0; y < 8; y++) {
        for (int x = 0; x < 8; x++) {
            GLuint r = (GLuint)(x * 1023 / 7), g = (GLuint)(y * 1023 / 7), b = (GLuint)((x ^ y) * 146), a = 3;
            texels[y * 8 + x] = r | (g << 10) | (b << 20) | (a << 30);
        }
    }
    GLuint tex[2];
    glGenTextures(2, tex);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB10_A2, 8, 8, 0, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV, texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB10_A2, 8, 8);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 8, 8, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV, texels);
    GLuint patch[4] = {1023u | (3u << 30), 1023u << 10 | (3u << 30), 1023u << 20 | (1u << 30), 0};
    glTexSubImage2D(GL_TEXTURE_2D, 0, 3, 3, 2, 2, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV, patch);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform sampler2D tex;\nout vec4 color;\n"
        "void main() { vec4 t = texture(tex, uv); color = vec4(t.rgb * t.a, 1.0); }\n");
    glUseProgram(show);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glScissor(0, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glScissor(32, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_SCISSOR_TEST);
    eglSwapBuffers(dpy, surf);
}

/* An unsigned small float of `mbits` mantissa bits (5-bit exponent, bias 15) for v in [0, 2). */
static GLuint small_float(float v, int mbits) {
    if (v <= 0.0f) return 0;
    int e = 15;
    while (v < 1.0f && e > 1) { v *= 2.0f; e--; }
    while (v >= 2.0f) { v *= 0.5f; e++; }
    if (v < 1.0f) return (GLuint)(v * (1 << mbits) * 0.5f + 0.5f); /* denormal at e = 1 */
    GLuint f = (GLuint)((v - 1.0f) * (1 << mbits) + 0.5f);
    if (f == (1u << mbits)) { f = 0; e++; }
    return ((GLuint)e << mbits) | f;
}

/* Packed float textures: GL_R11F_G11F_B10F by glTexImage2D with data (left half) and GL_RGB9_E5
 * by glTexStorage2D then glTexSubImage2D (right half), both linear. */
static void scene_packed_float(void) {
    GLuint r11[8 * 8], e5[8 * 8];
    for (int y = 0; y < 8; y++) {
        for (int x = 0; x < 8; x++) {
            float r = x / 7.0f, g = y / 7.0f, b = ((x ^ y) & 7) / 7.0f;
            r11[y * 8 + x] = small_float(r, 6) | (small_float(g, 6) << 11) | (small_float(b, 5) << 22);
            /* Exponent 15: a mantissa step is 2^-9. */
            GLuint mr = (GLuint)(r * 511.0f + 0.5f), mg = (GLuint)(g * 511.0f + 0.5f), mb = (GLuint)(b * 511.0f + 0.5f);
            e5[y * 8 + x] = mr | (mg << 9) | (mb << 18) | (15u << 27);
        }
    }
    GLuint tex[2];
    glGenTextures(2, tex);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R11F_G11F_B10F, 8, 8, 0, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV, r11);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB9_E5, 8, 8);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 8, 8, GL_RGB, GL_UNSIGNED_INT_5_9_9_9_REV, e5);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform sampler2D tex;\nout vec4 color;\n"
        "void main() { color = texture(tex, uv); }\n");
    glUseProgram(show);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glScissor(0, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glScissor(32, 0, 32, 64);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_SCISSOR_TEST);
    eglSwapBuffers(dpy, surf);
}

/* Primitive restart (always on in GL ES 3.0 as GL_PRIMITIVE_RESTART_FIXED_INDEX) with short and
 * byte indices, and glDrawRangeElements. */
static void scene_restart(void) {
    GLuint p = program(color_vs, color_fs);
    glUseProgram(p);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    float vertices[16 * 6];
    for (int i = 0; i < 16; i++) {
        float *v = vertices + i * 6;
        v[0] = -0.9f + (i / 2) * 0.25f;
        v[1] = (i % 2) ? 0.8f : 0.1f;
        v[2] = (i % 3) * 0.4f; v[3] = 1.0f - (i % 4) * 0.25f; v[4] = (i % 5) * 0.2f; v[5] = 1;
    }
    buffer(GL_ARRAY_BUFFER, sizeof vertices, vertices);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(2 * sizeof(float)));
    const GLushort strips[] = {0, 1, 2, 3, 0xFFFF, 4, 5, 6, 7, 8, 9, 0xFFFF, 12, 13, 14, 15};
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof strips, strips);
    glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
    glClearColor(0.1f, 0.1f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawElements(GL_TRIANGLE_STRIP, 16, GL_UNSIGNED_SHORT, (void *)0);
    /* the bottom row: byte indices with restart, then a range-elements draw without restart */
    const GLubyte bytes[] = {0, 1, 2, 0xFF, 2, 3, 4, 0xFF, 6, 7, 8};
    GLuint vao2;
    glGenVertexArrays(1, &vao2);
    glBindVertexArray(vao2);
    float low[16 * 6];
    memcpy(low, vertices, sizeof low);
    for (int i = 0; i < 16; i++) low[i * 6 + 1] -= 1.0f;
    buffer(GL_ARRAY_BUFFER, sizeof low, low);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(2 * sizeof(float)));
    buffer(GL_ELEMENT_ARRAY_BUFFER, sizeof bytes, bytes);
    glDrawElements(GL_TRIANGLE_STRIP, 11, GL_UNSIGNED_BYTE, (void *)0);
    glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
    const GLushort range[] = {10, 11, 12, 12, 11, 13};
    GLuint ib;
    glGenBuffers(1, &ib);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ib);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof range, range, GL_STATIC_DRAW);
    glDrawRangeElements(GL_TRIANGLES, 10, 13, 6, GL_UNSIGNED_SHORT, (void *)0);
    eglSwapBuffers(dpy, surf);
}

/* One 8x8 texture per format, each shown in a 16x16 cell: allocated by glTexImage2D without
 * data (or glTexStorage2D) and filled by glTexSubImage2D, partly at an offset. */
static void scene_formats(void) {
    GLuint show = program(show_vs,
        "#version 300 es\nprecision highp float;\nin vec2 uv;\nuniform sampler2D tex;\nuniform float scale;\n"
        "out vec4 color;\n"
        "void main() { color = texture(tex, uv) * scale; }\n");
    glUseProgram(show);
    GLint scale_location = glGetUniformLocation(show, "scale");
    quad_vao();
    glClearColor(0.5f, 0.0f, 0.5f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    unsigned char bytes[8 * 8 * 16];
    for (int i = 0; i < (int)sizeof bytes; i++) bytes[i] = (unsigned char)(i * 37 + (i >> 3) * 11);
    GLushort halves[8 * 8 * 4];
    float floats[8 * 8 * 4];
    for (int i = 0; i < 8 * 8 * 4; i++) {
        floats[i] = (float)((i * 7) % 23) / 11.0f;
        /* half floats of 0, 0.25, 0.5, ..., 1.75 */
        static const GLushort h[8] = {0x0000, 0x3400, 0x3800, 0x3A00, 0x3C00, 0x3D00, 0x3E00, 0x3F00};
        halves[i] = h[(i * 5) % 8];
    }
    struct { GLenum internal, format, type; const void *data; float scale; } formats[] = {
        {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_RG8, GL_RG, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_R8, GL_RED, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_RGB565, GL_RGB, GL_UNSIGNED_SHORT_5_6_5, bytes, 1},
        {GL_RGBA4, GL_RGBA, GL_UNSIGNED_SHORT_4_4_4_4, bytes, 1},
        {GL_RGB5_A1, GL_RGBA, GL_UNSIGNED_SHORT_5_5_5_1, bytes, 1},
        {GL_LUMINANCE_ALPHA, GL_LUMINANCE_ALPHA, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_ALPHA, GL_ALPHA, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_R16F, GL_RED, GL_HALF_FLOAT, halves, 0.5f},
        {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT, halves, 0.5f},
        {GL_R32F, GL_RED, GL_FLOAT, floats, 0.5f},
        {GL_RGBA32F, GL_RGBA, GL_FLOAT, floats, 0.5f},
        {GL_RG16F, GL_RG, GL_HALF_FLOAT, halves, 0.5f},
        {GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE, bytes, 1},
        {GL_LUMINANCE, GL_LUMINANCE, GL_UNSIGNED_BYTE, bytes, 1},
    };
    for (int i = 0; i < 16; i++) {
        GLuint tex;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        GLenum internal = formats[i].internal;
        if (internal == GL_LUMINANCE_ALPHA || internal == GL_ALPHA || internal == GL_LUMINANCE)
            glTexImage2D(GL_TEXTURE_2D, 0, internal, 8, 8, 0, formats[i].format, formats[i].type, NULL);
        else if (i % 2)
            glTexStorage2D(GL_TEXTURE_2D, 1, internal, 8, 8);
        else
            glTexImage2D(GL_TEXTURE_2D, 0, internal, 8, 8, 0, formats[i].format, formats[i].type, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        /* the whole level, then a 3x2 patch at (4, 5) from the same data */
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 8, 8, formats[i].format, formats[i].type, formats[i].data);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 4, 5, 3, 2, formats[i].format, formats[i].type, formats[i].data);
        glUniform1f(scale_location, formats[i].scale);
        glViewport((i % 4) * 16, (i / 4) * 16, 16, 16);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }
    eglSwapBuffers(dpy, surf);
}

/* Integer render targets and attributes: an RGBA8UI texture written through a uvec4 output
 * from an integer attribute (glVertexAttribIPointer) passed flat, read back with texelFetch
 * of a usampler2D; an R32I one cleared by glClearBufferiv. */
static void scene_integer(void) {
    GLuint write = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(location = 1) in uvec4 code;\n"
        "flat out uvec4 v_code;\n"
        "void main() { v_code = code; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision highp float;\nprecision highp int;\n"
        "flat in uvec4 v_code;\n"
        "layout(location = 0) out uvec4 color;\n"
        "layout(location = 1) out ivec4 signed_value;\n"
        "void main() {\n"
        "  uvec2 p = uvec2(gl_FragCoord.xy);\n"
        "  color = (v_code + uvec4(p.x * 7u, p.y * 5u, (p.x ^ p.y) << 2, 0u)) & 0xFFu;\n"
        "  signed_value = ivec4(int(p.x) - 16, -int(p.y), int(v_code.x) * -3, 7);\n"
        "}\n");
    GLuint tex[2];
    glGenTextures(2, tex);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8UI, 32, 32);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32I, 32, 32, 0, GL_RED_INTEGER, GL_INT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[1], 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("integer framebuffer");
    glViewport(0, 0, 32, 32);
    const GLuint clear_u[4] = {10, 20, 30, 255};
    const GLint clear_i[4] = {-5, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, clear_u);
    glClearBufferiv(GL_COLOR, 1, clear_i);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float tri[] = {-0.8f, -0.9f, 0.9f, -0.6f, -0.3f, 0.85f};
    buffer(GL_ARRAY_BUFFER, sizeof tri, tri);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    const GLushort codes[] = {200, 16, 64, 255, 3, 180, 90, 255, 77, 99, 250, 255};
    buffer(GL_ARRAY_BUFFER, sizeof codes, codes);
    glEnableVertexAttribArray(1);
    glVertexAttribIPointer(1, 4, GL_UNSIGNED_SHORT, 0, (void *)0);
    glUseProgram(write);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision highp float;\nprecision highp int;\n"
        "in vec2 uv;\nuniform highp usampler2D codes;\nuniform highp isampler2D values;\nout vec4 color;\n"
        "void main() {\n"
        "  ivec2 texel = ivec2(uv * vec2(textureSize(codes, 0)));\n"
        "  if (uv.x < 0.5) color = vec4(texelFetch(codes, texel, 0)) / 255.0;\n"
        "  else { ivec4 v = texelFetch(values, texel, 0); color = vec4(vec3(v.xyz) / 40.0 + 0.5, 1.0); }\n"
        "}\n");
    glUseProgram(show);
    glUniform1i(glGetUniformLocation(show, "codes"), 0);
    glUniform1i(glGetUniformLocation(show, "values"), 1);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    quad_vao();
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Float and sRGB render targets: additive blending past 1.0 into RGBA16F (then scaled down
 * when shown), and blending into an SRGB8_ALPHA8 texture (blended in linear light, encoded on
 * write, decoded when sampled). */
static void scene_float_srgb(void) {
    GLuint p = gradient_program();
    GLuint tex[2];
    glGenTextures(2, tex);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA16F, 32, 64);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, 32, 64);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    GLuint fb[2];
    glGenFramebuffers(2, fb);
    glUseProgram(p);
    glEnable(GL_BLEND);
    for (int i = 0; i < 2; i++) {
        glBindFramebuffer(GL_FRAMEBUFFER, fb[i]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[i], 0);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("float/srgb framebuffer");
        glViewport(0, 0, 32, 64);
        glClearColor(0.25f, 0.5f, 0.125f, 0.5f);
        glClear(GL_COLOR_BUFFER_BIT);
        if (i == 0) glBlendFunc(GL_ONE, GL_ONE);
        else glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        draw_triangle();
        draw_triangle();
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    GLuint show = program(show_vs,
        "#version 300 es\nprecision highp float;\nin vec2 uv;\nuniform sampler2D tex;\nuniform float scale;\n"
        "out vec4 color;\n"
        "void main() { color = texture(tex, uv) * scale; }\n");
    glUseProgram(show);
    quad_vao();
    for (int i = 0; i < 2; i++) {
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glUniform1f(glGetUniformLocation(show, "scale"), i == 0 ? 0.4f : 1.0f);
        glViewport(i * 32, 0, 32, 64);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }
    eglSwapBuffers(dpy, surf);
}

/* glReadPixels in the middle of a frame, drawing on afterwards; a glMapBufferRange write with an
 * explicit flush; a fence. */
static void scene_readback(void) {
    GLuint p = gradient_program();
    glUseProgram(p);
    glClearColor(0.3f, 0.3f, 0.3f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    draw_triangle();
    unsigned char pixels[4 * 4 * 4];
    glReadPixels(30, 30, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000);
    glDeleteSync(fence);
    /* a quad whose colour is the pixel read back, at the top left */
    GLuint c = program(color_vs, color_fs);
    glUseProgram(c);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    GLuint vb;
    glGenBuffers(1, &vb);
    glBindBuffer(GL_ARRAY_BUFFER, vb);
    glBufferData(GL_ARRAY_BUFFER, 4 * 6 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    float *v = glMapBufferRange(GL_ARRAY_BUFFER, 0, 4 * 6 * sizeof(float),
                                GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT | GL_MAP_FLUSH_EXPLICIT_BIT);
    if (!v) die("map");
    const float corners[] = {-1, 0.5f, -0.5f, 0.5f, -1, 1, -0.5f, 1};
    for (int i = 0; i < 4; i++) {
        v[i * 6] = corners[2 * i];
        v[i * 6 + 1] = corners[2 * i + 1];
        for (int k = 0; k < 4; k++) v[i * 6 + 2 + k] = pixels[k] / 255.0f;
    }
    glFlushMappedBufferRange(GL_ARRAY_BUFFER, 0, 4 * 6 * sizeof(float));
    glUnmapBuffer(GL_ARRAY_BUFFER);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(2 * sizeof(float)));
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* A program whose vertex outputs `varyings` are captured by transform feedback in `mode`. */
static GLuint feedback_program(const char *vs, const char *fs, GLsizei n, const char *const *varyings, GLenum mode) {
    GLuint p = glCreateProgram();
    GLuint v = shader(GL_VERTEX_SHADER, vs), f = shader(GL_FRAGMENT_SHADER, fs);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glTransformFeedbackVaryings(p, n, varyings, mode);
    glLinkProgram(p);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        fprintf(stderr, "%s\n", log);
        die("link");
    }
    return p;
}

/* Transform feedback, then drawing what was captured. Left: six points captured with the
 * rasterizer off (INTERLEAVED: a doubled position and a tint, 28 bytes a vertex) into a
 * range of a buffer through a transform feedback object, a paused draw in between that must
 * not be captured, a clear under RASTERIZER_DISCARD; the captured vertices are then drawn as
 * two triangles. Right: a triangle strip drawn (grey, top) while captured as GL_TRIANGLES
 * (SEPARATE: gl_Position and a flat uint into two buffers), then drawn again from them moved
 * down, culling back faces (the strip's odd triangle keeps its winding) and coloured by the
 * captured ids. */
static void scene_feedback(void) {
    glClearColor(0.1f, 0.1f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);

    /* Left: points, interleaved, discarded. */
    const char *a_varyings[] = {"big", "tint"};
    GLuint a = feedback_program(
        "#version 300 es\nlayout(location = 0) in vec2 position;\nout vec4 big;\nout vec3 tint;\n"
        "void main() {\n"
        "  big = vec4(position * 2.0 - vec2(0.5, 0.0), 0.0, 1.0);\n"
        "  tint = vec3(position.x + 0.5, position.y + 0.5, float(gl_VertexID) / 6.0);\n"
        "  gl_Position = vec4(position, 0.0, 1.0);\n"
        "  gl_PointSize = 4.0;\n"
        "}\n",
        "#version 300 es\nprecision mediump float;\nout vec4 color;\nvoid main() { color = vec4(1.0, 0.0, 0.0, 1.0); }\n",
        2, a_varyings, GL_INTERLEAVED_ATTRIBS);
    const float points[] = {-0.2f, -0.2f, 0.2f, -0.2f, -0.2f, 0.2f, 0.2f, -0.2f, 0.2f, 0.2f, -0.2f, 0.2f};
    GLuint va[2];
    glGenVertexArrays(2, va);
    glBindVertexArray(va[0]);
    buffer(GL_ARRAY_BUFFER, sizeof points, points);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    const GLsizeiptr stride = 7 * sizeof(float);
    GLuint captured = buffer(GL_TRANSFORM_FEEDBACK_BUFFER, 7 * stride, NULL);
    GLuint tfo;
    glGenTransformFeedbacks(1, &tfo);
    glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, tfo);
    glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, captured, stride, 6 * stride);
    glUseProgram(a);
    glEnable(GL_RASTERIZER_DISCARD);
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, 3);
    glPauseTransformFeedback();
    glDrawArrays(GL_POINTS, 0, 6);
    glResumeTransformFeedback();
    glDrawArrays(GL_POINTS, 3, 3);
    glEndTransformFeedback();
    glDisable(GL_RASTERIZER_DISCARD);
    glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, 0);
    glDeleteTransformFeedbacks(1, &tfo);

    GLuint show_a = program(
        "#version 300 es\nlayout(location = 0) in vec4 position;\nlayout(location = 1) in vec3 tint;\n"
        "out vec3 v_tint;\nvoid main() { v_tint = tint; gl_Position = position; }\n",
        "#version 300 es\nprecision mediump float;\nin vec3 v_tint;\nout vec4 color;\n"
        "void main() { color = vec4(v_tint, 1.0); }\n");
    glBindVertexArray(va[1]);
    glBindBuffer(GL_ARRAY_BUFFER, captured);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride, (void *)stride);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, (void *)(stride + 4 * sizeof(float)));
    glUseProgram(show_a);
    glDrawArrays(GL_TRIANGLES, 0, 6);

    /* Right: a strip captured as triangles, separate buffers, rasterized too. */
    const char *b_varyings[] = {"gl_Position", "id"};
    GLuint b = feedback_program(
        "#version 300 es\nlayout(location = 0) in vec2 position;\nflat out uint id;\n"
        "void main() { id = uint(gl_VertexID); gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\nprecision mediump float;\nflat in uint id;\nout vec4 color;\n"
        "void main() { color = vec4(0.5, 0.5, 0.5 + 0.1 * float(id), 1.0); }\n",
        2, b_varyings, GL_SEPARATE_ATTRIBS);
    const float strip[] = {0.1f, 0.1f, 0.9f, 0.1f, 0.1f, 0.9f, 0.9f, 0.9f};
    GLuint vb[2];
    glGenVertexArrays(2, vb);
    glBindVertexArray(vb[0]);
    buffer(GL_ARRAY_BUFFER, sizeof strip, strip);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    GLuint positions = buffer(GL_TRANSFORM_FEEDBACK_BUFFER, 6 * 4 * sizeof(float), NULL);
    GLuint ids = buffer(GL_TRANSFORM_FEEDBACK_BUFFER, 6 * sizeof(GLuint), NULL);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, positions);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 1, ids);
    glUseProgram(b);
    glBeginTransformFeedback(GL_TRIANGLES);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glEndTransformFeedback();

    GLuint show_b = program(
        "#version 300 es\nlayout(location = 0) in vec4 position;\nlayout(location = 1) in uint id;\n"
        "flat out uint v_id;\nvoid main() { v_id = id; gl_Position = position - vec4(0.0, 1.0, 0.0, 0.0); }\n",
        "#version 300 es\nprecision mediump float;\nflat in uint v_id;\nout vec4 color;\n"
        "void main() { color = vec4(float(v_id & 1u), float((v_id >> 1) & 1u), 0.25 * float(v_id), 1.0); }\n");
    glBindVertexArray(vb[1]);
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glBindBuffer(GL_ARRAY_BUFFER, ids);
    glEnableVertexAttribArray(1);
    glVertexAttribIPointer(1, 1, GL_UNSIGNED_INT, 0, (void *)0);
    glUseProgram(show_b);
    glEnable(GL_CULL_FACE);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glDisable(GL_CULL_FACE);
    eglSwapBuffers(dpy, surf);
}

/* GLSL ES 3.00 language features real shaders use: integer and bit operations, switch,
 * do-while, structs and arrays, non-square matrices, inverse/transpose, textureSize,
 * texelFetch, textureGrad, textureOffset, packing functions, float bit casts. */
static void scene_glsl3_more(void) {
    GLuint p = program(show_vs,
        "#version 300 es\n"
        "precision highp float;\nprecision highp int;\n"
        "in vec2 uv;\n"
        "uniform sampler2D tex;\n"
        "uniform ivec2 offset_choice;\n"
        "uniform uint mask;\n"
        "out vec4 color;\n"
        "struct Light { vec3 direction; float power; };\n"
        "const Light lights[2] = Light[2](Light(vec3(0.0, 0.6, 0.8), 1.0), Light(vec3(0.8, 0.0, 0.6), 0.5));\n"
        "float shade(Light l, vec3 n) { return max(dot(n, l.direction), 0.0) * l.power; }\n"
        "void main() {\n"
        "  ivec2 cell = ivec2(uv * 8.0);\n"
        "  int which = (cell.x + cell.y * 8) % 6;\n"
        "  vec4 c = vec4(0.0);\n"
        "  switch (which) {\n"
        "    case 0: c = texture(tex, uv); break;\n"
        "    case 1: c = texelFetch(tex, ivec2(uv * vec2(textureSize(tex, 0))), 0); break;\n"
        "    case 2: c = textureGrad(tex, uv, vec2(0.1, 0.0), vec2(0.0, 0.1)); break;\n"
        "    case 3: c = textureOffset(tex, uv, ivec2(2, -1)); break;\n"
        "    case 4: {\n"
        "      mat2x3 m = mat2x3(1.0, 0.5, 0.2, 0.3, 0.9, 0.1);\n"
        "      mat3 r = inverse(mat3(2.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.1, 0.0, 1.0));\n"
        "      vec3 n = normalize(r * (m * uv) + transpose(m)[0].xyx * 0.1);\n"
        "      c = vec4(shade(lights[0], n), shade(lights[1], n), n.z, 1.0);\n"
        "      break;\n"
        "    }\n"
        "    default: {\n"
        "      uint bits = packUnorm2x16(uv);\n"
        "      uint v = (bits ^ mask) >> 3u;\n"
        "      int count = 0;\n"
        "      do { count += int(v & 1u); v >>= 1u; } while (v != 0u);\n"
        "      float f = intBitsToFloat(floatBitsToInt(uv.x) & ~0xFFFF);\n"
        "      c = vec4(float(count) / 32.0, f, float(uint(which) * 40u % 256u) / 255.0, 1.0);\n"
        "    }\n"
        "  }\n"
        "  color = c;\n"
        "}\n");
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "mask"), 0xA5A5A5A5u);
    unsigned char texels[16 * 16 * 4];
    for (int i = 0; i < 16 * 16; i++) {
        texels[i * 4] = (unsigned char)((i % 16) * 16);
        texels[i * 4 + 1] = (unsigned char)((i / 16) * 16);
        texels[i * 4 + 2] = ((i % 16) / 4 + (i / 64)) % 2 ? 220 : 30;
        texels[i * 4 + 3] = 255;
    }
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* ---- scenes added by the glsl4 work (flat varyings, switch, integer arithmetic) ---- */

/* flat varyings: a vec4 colour, an int and a uint passed flat (GL's provoking vertex is each
 * primitive's last: strips and fans too), over a strip (left), a fan (middle), a list (right)
 * and a list triangle whose last vertex lies beyond the far plane, so it is clipped away. */
static void scene_flat(void) {
    GLuint p = program(
        "#version 300 es\n"
        "layout(location = 0) in vec3 position;\n"
        "layout(location = 1) in vec4 color;\n"
        "flat out vec4 v_color;\n"
        "flat out int v_id;\n"
        "flat out uint v_bits;\n"
        "out float v_smooth;\n"
        "void main() {\n"
        "  v_color = color;\n"
        "  v_id = gl_VertexID * 3 - 7;\n"
        "  v_bits = 0x9E3779B9u * uint(gl_VertexID + 1);\n"
        "  v_smooth = color.r;\n"
        "  gl_Position = vec4(position, 1.0);\n"
        "}\n",
        "#version 300 es\n"
        "precision highp float;\nprecision highp int;\n"
        "flat in vec4 v_color;\n"
        "flat in int v_id;\n"
        "flat in uint v_bits;\n"
        "in float v_smooth;\n"
        "out vec4 color;\n"
        "void main() {\n"
        "  float id = float(v_id + 7) / 48.0;\n"
        "  float bits = float(v_bits >> 24) / 255.0;\n"
        "  color = vec4(v_color.r * 0.5 + id, v_color.g * 0.5 + bits * 0.5, v_color.b, 1.0);\n"
        "  if (v_smooth > 2.0) color = vec4(1.0);\n"
        "}\n");
    glUseProgram(p);
    /* x, y, z, then r, g, b, a per vertex. */
    const float v[] = {
        /* strip, 6 vertices: 4 triangles in x in [-1, -0.4] */
        -1.0f, -0.9f, 0.0f, 1, 0, 0, 1, -1.0f, 0.9f, 0.0f, 0, 1, 0, 1, -0.8f, -0.9f, 0.0f, 0, 0, 1, 1,
        -0.8f, 0.9f, 0.0f, 1, 1, 0, 1, -0.4f, -0.9f, 0.0f, 0, 1, 1, 1, -0.4f, 0.9f, 0.0f, 1, 0, 1, 1,
        /* fan, 5 vertices: 3 triangles around (0, 0) */
        -0.1f, 0.0f, 0.0f, 0.2f, 0.2f, 0.2f, 1, -0.3f, -0.9f, 0.0f, 1, 0.5f, 0, 1, 0.2f, -0.9f, 0.0f, 0, 0.5f, 1, 1,
        0.2f, 0.9f, 0.0f, 0.5f, 1, 0, 1, -0.3f, 0.9f, 0.0f, 1, 1, 1, 1,
        /* list, 2 triangles */
        0.3f, -0.9f, 0.0f, 1, 0, 0, 1, 0.9f, -0.9f, 0.0f, 0, 1, 0, 1, 0.3f, -0.1f, 0.0f, 0, 0, 1, 1,
        0.9f, -0.9f, 0.0f, 0.5f, 0, 0, 1, 0.9f, -0.1f, 0.0f, 0, 0.5f, 0, 1, 0.3f, -0.1f, 0.0f, 0, 0.8f, 0.8f, 1,
        /* a triangle whose last vertex is beyond the far plane (clipped) */
        0.3f, 0.1f, 0.0f, 1, 1, 0, 1, 0.9f, 0.1f, 0.0f, 0, 1, 1, 1, 0.6f, 0.9f, 3.0f, 1, 0.3f, 0.6f, 1,
    };
    GLuint vao;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    buffer(GL_ARRAY_BUFFER, sizeof v, v);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 7 * sizeof(float), (void *)(3 * sizeof(float)));
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 6);
    glDrawArrays(GL_TRIANGLE_FAN, 6, 5);
    glDrawArrays(GL_TRIANGLES, 11, 9);
    eglSwapBuffers(dpy, surf);
}

/* switch and 32-bit integer arithmetic: a per-pixel hash (wrapping uint multiply, xor,
 * shifts), int division and remainder of non-negative values, min/max/clamp/abs on ints,
 * bitwise not, uint compares above 2^31, int<->float conversions, selected by a switch with
 * fall-through and a default in the middle; all defined by GLSL ES 3.00. */
static void scene_int_switch(void) {
    GLuint p = program(show_vs,
        "#version 300 es\n"
        "precision highp float;\nprecision highp int;\n"
        "in vec2 uv;\n"
        "uniform uint seed;\n"
        "out vec4 color;\n"
        "uint hash(uint x) {\n"
        "  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;\n"
        "  return x;\n"
        "}\n"
        "void main() {\n"
        "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
        "  int cell = (p.x / 8) + (p.y / 8) * 8;\n"
        "  uint h = hash(uint(p.x) | (uint(p.y) << 8) | (seed << 16));\n"
        "  vec3 c = vec3(0.0);\n"
        "  switch (cell % 7) {\n"
        "    case 0: c = vec3(float(h & 255u), float((h >> 8) & 255u), float(h >> 24)) / 255.0; break;\n"
        "    case 1: c.r = float(p.x * 37 % 64) / 63.0;\n"
        "    case 2: c.g = float(clamp(p.y * 5 - 40, 0, 255)) / 255.0; break;\n"
        "    default: c = vec3(float(~h >> 30) / 3.0, float(h > 0x80000000u), 0.5); break;\n"
        "    case 3: { int a = abs(p.x - 32) * 7 / 3; c = vec3(float(min(a, 60)) / 60.0, float(max(a - 20, 0)) / 60.0, 0.2); break; }\n"
        "    case 4: c = vec3(float(uint(p.x) * 0xFFFFFFF1u >> 26) / 63.0, float(int(uv.x * 100.0) % 10) / 9.0, float((h >> 3) % 32u) / 31.0);\n"
        "  }\n"
        "  color = vec4(c, 1.0);\n"
        "}\n");
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "seed"), 0xBEEFu);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* ---- Scenes of the tex3d branch: 2-D array and 3-D textures. ---- */

/* Layer k of w x h x d: texel (x, y) = (x * 255 / (w - 1), y * 255 / (h - 1), 60 k, 255),
 * with a checker of the layer's own in alpha-free blue. */
static unsigned char *layered_texels(int w, int h, int d) {
    unsigned char *t = malloc((size_t)w * h * d * 4);
    for (int k = 0; k < d; k++)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                unsigned char *p = t + (((size_t)k * h + y) * w + x) * 4;
                p[0] = (unsigned char)(x * 255 / (w - 1));
                p[1] = (unsigned char)(y * 255 / (h - 1));
                p[2] = (unsigned char)((60 * k + ((x / 2 + y / 2) % 2) * 40) % 256);
                p[3] = 255;
            }
    return t;
}

/* 2-D array textures: a 16x16x4 array by glTexImage3D with a glTexSubImage3D patch in
 * layer 2, mip-mapped by glGenerateMipmap and minified trilinear with the layer changing
 * across the window (top half, `texture`); an 8x8x3 array by glTexStorage3D filled by
 * glTexSubImage3D, read by `textureLod` at level 0 with nearest filtering (bottom half). */
static void scene_array(void) {
    GLuint tex[2];
    glGenTextures(2, tex);
    unsigned char *texels = layered_texels(16, 16, 4);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tex[0]);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, 16, 16, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    unsigned char patch[4 * 4 * 4];
    for (int i = 0; i < 16; i++) {
        patch[i * 4] = 255;
        patch[i * 4 + 1] = 0;
        patch[i * 4 + 2] = 255;
        patch[i * 4 + 3] = 255;
    }
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 6, 6, 2, 4, 4, 1, GL_RGBA, GL_UNSIGNED_BYTE, patch);
    glGenerateMipmap(GL_TEXTURE_2D_ARRAY);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tex[1]);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA8, 8, 8, 3);
    unsigned char *small = layered_texels(8, 8, 3);
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, 8, 8, 3, GL_RGBA, GL_UNSIGNED_BYTE, small);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    GLuint p = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\n"
        "uniform mediump sampler2DArray big;\nuniform mediump sampler2DArray small;\nout vec4 color;\n"
        "void main() {\n"
        "  if (uv.y > 0.5) color = texture(big, vec3(uv * 5.0, uv.x * 3.0 + 0.2));\n"
        "  else color = textureLod(small, vec3(uv.x * 1.3 - 0.1, uv.y * 2.0, uv.x * 2.6 - 0.2), 0.0);\n"
        "}\n");
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "big"), 0);
    glUniform1i(glGetUniformLocation(p, "small"), 1);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
    free(texels);
    free(small);
}

/* Rendering into layers (glFramebufferTextureLayer): layer 1 of a 16x16x3 2-D array (given
 * texels, loaded: a triangle drawn over them) and slice 2 of an 8x8x4 3-D texture (cleared,
 * then a smaller triangle), both then sampled nearest in the window: the array's three
 * layers side by side on top, the volume's four slices below. */
static void scene_layer(void) {
    GLuint tex[2];
    glGenTextures(2, tex);
    unsigned char *texels = layered_texels(16, 16, 3);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tex[0]);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA8, 16, 16, 3);
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, 16, 16, 3, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    unsigned char *slices = layered_texels(8, 8, 4);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, tex[1]);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, 8, 8, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, slices);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

    GLuint fill = program(color_vs, color_fs);
    GLuint fb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, tex[0], 0, 1);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("array layer incomplete");
    glViewport(0, 0, 16, 16);
    glUseProgram(fill);
    const float tri[] = {-0.8f, -0.8f, 1, 1, 0, 1, 0.8f, -0.8f, 0, 1, 1, 1, -0.8f, 0.8f, 1, 0, 1, 1};
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), tri);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), tri + 2);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, tex[1], 0, 2);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("volume slice incomplete");
    glViewport(0, 0, 8, 8);
    glClearColor(0.2f, 0.4f, 0.6f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    const float small[] = {-0.5f, -0.5f, 1, 0.5f, 0, 1, 0.5f, -0.5f, 1, 0.5f, 0, 1, 0, 0.5f, 1, 0.5f, 0, 1};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), small);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), small + 2);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisableVertexAttribArray(1);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);

    GLuint p = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\n"
        "uniform mediump sampler2DArray layers;\nuniform mediump sampler3D slices;\nout vec4 color;\n"
        "void main() {\n"
        "  if (uv.y > 0.5) color = texture(layers, vec3(fract(uv.x * 3.0), uv.y * 2.0 - 1.0, floor(uv.x * 3.0)));\n"
        "  else color = texture(slices, vec3(fract(uv.x * 4.0), uv.y * 2.0, (floor(uv.x * 4.0) + 0.5) / 4.0));\n"
        "}\n");
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "layers"), 0);
    glUniform1i(glGetUniformLocation(p, "slices"), 1);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
    free(texels);
    free(slices);
}

/* Copies into layers (glCopyTexSubImage3D): the window's picture (a clear and a triangle)
 * copied into a patch of layer 1 of a 16x16x3 2-D array and into slice 0 of an 8x8x2 3-D
 * texture, then both sampled nearest over the cleared window. */
static void scene_copy_layer(void) {
    GLuint tex[2];
    glGenTextures(2, tex);
    unsigned char *texels = layered_texels(16, 16, 3);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tex[0]);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, 16, 16, 3, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    unsigned char *slices = layered_texels(8, 8, 2);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, tex[1]);
    glTexStorage3D(GL_TEXTURE_3D, 1, GL_RGBA8, 8, 8, 2);
    glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, 8, 8, 2, GL_RGBA, GL_UNSIGNED_BYTE, slices);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

    glClearColor(0.9f, 0.1f, 0.3f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    GLuint fill = program(color_vs, color_fs);
    glUseProgram(fill);
    const float tri[] = {-1, -1, 1, 1, 0, 1, 0, -1, 0, 1, 1, 1, -1, 0, 1, 0, 1, 1};
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), tri);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), tri + 2);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisableVertexAttribArray(1);
    glActiveTexture(GL_TEXTURE0);
    glCopyTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 4, 2, 1, 0, 0, 10, 12);
    glActiveTexture(GL_TEXTURE1);
    glCopyTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, 4, 4, 8, 8);

    GLuint p = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\n"
        "uniform mediump sampler2DArray layers;\nuniform mediump sampler3D slices;\nout vec4 color;\n"
        "void main() {\n"
        "  if (uv.y > 0.5) color = texture(layers, vec3(fract(uv.x * 3.0), uv.y * 2.0 - 1.0, floor(uv.x * 3.0)));\n"
        "  else color = texture(slices, vec3(fract(uv.x * 2.0), uv.y * 2.0, (floor(uv.x * 2.0) + 0.5) / 2.0));\n"
        "}\n");
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "layers"), 0);
    glUniform1i(glGetUniformLocation(p, "slices"), 1);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
    free(texels);
    free(slices);
}

/* 3-D textures: an 8x8x8 texture by glTexStorage3D + glTexSubImage3D, linear in all three
 * coordinates with WRAP_R repeat (left half), a 4x4x6 one by glTexImage3D, nearest, WRAP_R
 * clamp-to-edge and mirrored S (right half); r runs across the window past [0, 1]. */
static void scene_volume(void) {
    GLuint tex[2];
    glGenTextures(2, tex);
    unsigned char *texels = layered_texels(8, 8, 8);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_3D, tex[0]);
    glTexStorage3D(GL_TEXTURE_3D, 1, GL_RGBA8, 8, 8, 8);
    glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, 8, 8, 8, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_REPEAT);
    unsigned char *small = layered_texels(4, 4, 6);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, tex[1]);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, 4, 4, 6, 0, GL_RGBA, GL_UNSIGNED_BYTE, small);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_MIRRORED_REPEAT);
    GLuint p = program(show_vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\n"
        "uniform mediump sampler3D smooth_volume;\nuniform mediump sampler3D blocky;\nout vec4 color;\n"
        "void main() {\n"
        "  vec3 c = vec3(uv.y * 1.1, uv.x * 0.7 + 0.05, uv.x * 1.7 + uv.y * 0.45 - 0.3);\n"
        "  if (uv.x < 0.5) color = texture(smooth_volume, c);\n"
        "  else color = texture(blocky, c * vec3(1.6, 1.0, 1.0));\n"
        "}\n");
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "smooth_volume"), 0);
    glUniform1i(glGetUniformLocation(p, "blocky"), 1);
    quad_vao();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
    free(texels);
    free(small);
}

/* texfn: the quadrants of the window, each drawn in its own viewport with uv in [0, 1].
 * Top left: textureGrad on a 16x16 texture with 5 levels of distinct colours (a checker on
 * level 0), trilinear, the x derivative 1, 2.5, 6 and 12 texels per pixel in four strips.
 * Top right: textureOffset (nearest, magnified) and textureLodOffset (linear, level 0) near
 * the edges of an 8x8 texture, clamped on the left half and repeated on the right.
 * Bottom left: a cube with given levels whose own filter reads level 0, through a sampler
 * object reading level 1 by textureLod. Bottom right: a 3-D texture whose own WRAP_R repeats,
 * through a sampler object whose WRAP_R clamps, r running from -0.5 to 1.5. */
static void scene_texfn(void) {
    const char *vs =
        "#version 300 es\n"
        "out vec2 uv;\n"
        "void main() {\n"
        "  vec2 corner = vec2(float(gl_VertexID % 2), float(gl_VertexID / 2));\n"
        "  uv = corner;\n"
        "  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);\n"
        "}\n";
    GLuint grad = program(vs,
        "#version 300 es\nprecision highp float;\nin vec2 uv;\nuniform sampler2D tex;\nout vec4 color;\n"
        "void main() {\n"
        "  float strip = floor(uv.x * 4.0);\n"
        "  float k = strip == 0.0 ? 1.0 : strip == 1.0 ? 2.5 : strip == 2.0 ? 6.0 : 12.0;\n"
        "  color = textureGrad(tex, uv * 2.0, vec2(k / 16.0, 0.0), vec2(0.0, 1.0 / 16.0));\n"
        "}\n");
    GLuint offsets = program(vs,
        "#version 300 es\nprecision highp float;\nin vec2 uv;\nuniform sampler2D clamped;\n"
        "uniform sampler2D repeated;\nuniform sampler2D smooth_clamped;\nout vec4 color;\n"
        "void main() {\n"
        "  vec2 p = vec2(fract(uv.x * 2.0), uv.y) * 1.5 - 0.25;\n"
        "  bool left = uv.x < 0.5;\n"
        "  if (uv.y < 0.5)\n"
        "    color = left ? textureOffset(clamped, p, ivec2(-3, 2)) : textureOffset(repeated, p, ivec2(5, -7));\n"
        "  else\n"
        "    color = left ? textureLodOffset(smooth_clamped, p, 0.0, ivec2(7, -8))\n"
        "                 : textureProjOffset(repeated, vec3(p * 2.0, 2.0), ivec2(-1, 1));\n"
        "}\n");
    GLuint cube = program(vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform samplerCube env;\nout vec4 color;\n"
        "void main() { color = textureLod(env, vec3(uv * 2.0 - 1.0, -1.0), 1.0); }\n");
    GLuint volume = program(vs,
        "#version 300 es\nprecision mediump float;\nin vec2 uv;\nuniform mediump sampler3D vol;\nout vec4 color;\n"
        "void main() { color = texture(vol, vec3(uv.y, 0.5, uv.x * 2.0 - 0.5)); }\n");
    quad_vao();

    /* The 16x16 texture with 5 levels. */
    GLuint mipped;
    glGenTextures(1, &mipped);
    glBindTexture(GL_TEXTURE_2D, mipped);
    glTexStorage2D(GL_TEXTURE_2D, 5, GL_RGBA8, 16, 16);
    const unsigned char level_colors[5][4] = {
        {240, 30, 30, 255}, {30, 220, 40, 255}, {40, 60, 230, 255}, {230, 220, 40, 255}, {200, 40, 210, 255}};
    unsigned char texels[16 * 16 * 4];
    for (int level = 0; level < 5; level++) {
        int size = 16 >> level;
        for (int i = 0; i < size * size; i++) {
            memcpy(texels + i * 4, level_colors[level], 4);
            if (level == 0 && ((i % 16) / 2 + i / 32) % 2) texels[i * 4 + 1] = 160;
        }
        glTexSubImage2D(GL_TEXTURE_2D, level, 0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);

    /* Three 8x8 textures of the same distinct texels. */
    for (int i = 0; i < 64; i++) {
        texels[i * 4] = (unsigned char)((i % 8) * 32 + 8);
        texels[i * 4 + 1] = (unsigned char)((i / 8) * 32 + 8);
        texels[i * 4 + 2] = (unsigned char)(((i % 8) ^ (i / 8)) & 1 ? 220 : 30);
        texels[i * 4 + 3] = 255;
    }
    GLuint small[3];
    glGenTextures(3, small);
    for (int t = 0; t < 3; t++) {
        glActiveTexture(GL_TEXTURE1 + t);
        glBindTexture(GL_TEXTURE_2D, small[t]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        GLint wrap = t == 1 ? GL_REPEAT : GL_CLAMP_TO_EDGE;
        GLint filter = t == 2 ? GL_LINEAR : GL_NEAREST;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    }

    /* The cube: 4x4 faces, levels 0, 1, 2 each its own colour per face. */
    glActiveTexture(GL_TEXTURE4);
    GLuint env;
    glGenTextures(1, &env);
    glBindTexture(GL_TEXTURE_CUBE_MAP, env);
    for (int face = 0; face < 6; face++)
        for (int level = 0; level < 3; level++) {
            int size = 4 >> level;
            for (int i = 0; i < size * size; i++) {
                texels[i * 4] = (unsigned char)(40 + 80 * level);
                texels[i * 4 + 1] = (unsigned char)(30 * face + ((i % size + i / size) % 2) * 40);
                texels[i * 4 + 2] = (unsigned char)(200 - 80 * level);
                texels[i * 4 + 3] = 255;
            }
            glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, level, GL_RGBA, size, size, 0, GL_RGBA,
                         GL_UNSIGNED_BYTE, texels);
        }
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

    /* The 3-D texture: 4x4x4, slice k its own colour; its own WRAP_R repeats. */
    glActiveTexture(GL_TEXTURE5);
    GLuint vol;
    glGenTextures(1, &vol);
    glBindTexture(GL_TEXTURE_3D, vol);
    unsigned char slices[4 * 4 * 4 * 4];
    for (int i = 0; i < 64; i++) {
        int k = i / 16;
        slices[i * 4] = (unsigned char)(30 + 60 * k);
        slices[i * 4 + 1] = (unsigned char)(220 - 50 * k);
        slices[i * 4 + 2] = (unsigned char)((i % 4) * 60);
        slices[i * 4 + 3] = 255;
    }
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, 4, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, slices);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_REPEAT);

    /* Sampler objects on units 4 (cube: level 1) and 5 (3-D: WRAP_R clamps). */
    GLuint samplers[2];
    glGenSamplers(2, samplers);
    glSamplerParameteri(samplers[0], GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glSamplerParameteri(samplers[0], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(samplers[1], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(samplers[1], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(samplers[1], GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glBindSampler(4, samplers[0]);
    glBindSampler(5, samplers[1]);

    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glViewport(0, 32, 32, 32);
    glUseProgram(grad);
    glUniform1i(glGetUniformLocation(grad, "tex"), 0);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glViewport(32, 32, 32, 32);
    glUseProgram(offsets);
    glUniform1i(glGetUniformLocation(offsets, "clamped"), 1);
    glUniform1i(glGetUniformLocation(offsets, "repeated"), 2);
    glUniform1i(glGetUniformLocation(offsets, "smooth_clamped"), 3);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glViewport(0, 0, 32, 32);
    glUseProgram(cube);
    glUniform1i(glGetUniformLocation(cube, "env"), 4);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glViewport(32, 0, 32, 32);
    glUseProgram(volume);
    glUniform1i(glGetUniformLocation(volume, "vol"), 5);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    eglSwapBuffers(dpy, surf);
}

/* Two live contexts sharing objects, drawing interleaved: the window's context ("win") keeps
 * its clear colour, blending, program, vertex array and texture binding; a second one
 * ("off", current without a surface) keeps its framebuffer binding, viewport, program and
 * attributes. Each sets its state once: "off" draws into a texture, "win" samples it on the
 * left, "off" draws into it again, "win" samples it on the right. */
static void scene_contexts(void) {
    EGLint ctx_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE};
    EGLContext off = eglCreateContext(dpy, config, ctx, ctx_attribs);
    if (off == EGL_NO_CONTEXT) die("eglCreateContext (second)");

    /* win: a textured quad program, a vertex array, blending and a clear colour. */
    GLuint show = program(
        "#version 300 es\n"
        "layout(location = 0) in vec2 position;\n"
        "layout(location = 1) in vec2 uv_in;\n"
        "out vec2 uv;\n"
        "void main() { uv = uv_in; gl_Position = vec4(position, 0.0, 1.0); }\n",
        "#version 300 es\n"
        "precision mediump float;\n"
        "in vec2 uv;\n"
        "uniform sampler2D image;\n"
        "out vec4 color;\n"
        "void main() { color = vec4(texture(image, uv).rgb, 0.75); }\n");
    glUseProgram(show);
    GLuint win_vao;
    glGenVertexArrays(1, &win_vao);
    glBindVertexArray(win_vao);
    const float quads[] = {-0.9f, -0.8f, 0, 0, -0.1f, -0.8f, 1, 0, -0.9f, 0.8f, 0, 1, -0.1f, 0.8f, 1, 1,
                           0.1f,  -0.8f, 0, 0, 0.9f,  -0.8f, 1, 0, 0.1f,  0.8f, 0, 1, 0.9f,  0.8f, 1, 1};
    buffer(GL_ARRAY_BUFFER, sizeof quads, quads);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (void *)(2 * sizeof(float)));
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glClearColor(0.1f, 0.3f, 0.5f, 1);
    GLuint tex;
    glGenTextures(1, &tex);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glUniform1i(glGetUniformLocation(show, "image"), 1);
    glClear(GL_COLOR_BUFFER_BIT);

    /* off: its own framebuffer (name 1 again: framebuffers and vertex arrays are each
     * context's), viewport, program and client-side attributes; no blending. */
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, off)) die("eglMakeCurrent (off)");
    GLuint paint = program(color_vs, color_fs);
    glUseProgram(paint);
    GLuint fb, off_vao;
    glGenFramebuffers(1, &fb);
    glGenVertexArrays(1, &off_vao);
    glBindVertexArray(off_vao);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("framebuffer");
    glViewport(0, 0, 16, 16);
    glClearColor(0.9f, 0.9f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    const float tri[] = {-1, -1, 1, -1, -1, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 1};
    GLuint tri_buffer = buffer(GL_ARRAY_BUFFER, sizeof tri, tri);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, (void *)(6 * sizeof(float)));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFlush();

    /* win: nothing rebound; the left quad shows the texture. */
    if (!eglMakeCurrent(dpy, surf, surf, ctx)) die("eglMakeCurrent (win)");
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);

    /* off: nothing rebound; a second triangle over the first, with a constant colour. */
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, off)) die("eglMakeCurrent (off)");
    const float tri2[] = {1, 1, -1, 1, 1, -1};
    glBindBuffer(GL_ARRAY_BUFFER, tri_buffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof tri2, tri2);
    glDisableVertexAttribArray(1);
    glVertexAttrib4f(1, 0.8f, 0.2f, 0.9f, 1);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFlush();

    /* win: the right quad shows it changed; a clear of a scissored strip with win's colour. */
    if (!eglMakeCurrent(dpy, surf, surf, ctx)) die("eglMakeCurrent (win)");
    glDrawArrays(GL_TRIANGLE_STRIP, 4, 4);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, W, 4);
    glClear(GL_COLOR_BUFFER_BIT);
    eglSwapBuffers(dpy, surf);
}

int main(int argc, char **argv) {
    const struct { const char *name; void (*draw)(void); } scenes[] = {
        {"vao", scene_vao}, {"instanced", scene_instanced}, {"ubo", scene_ubo}, {"glsl3", scene_glsl3},
        {"objects", scene_objects}, {"mrt", scene_mrt}, {"blit", scene_blit},
        {"invalidate", scene_invalidate}, {"shadow", scene_shadow}, {"shadow-sampler", scene_shadow_sampler}, {"rgb10a2", scene_rgb10a2},
        {"packed-float", scene_packed_float}, {"restart", scene_restart},
        {"formats", scene_formats}, {"integer", scene_integer}, {"float-srgb", scene_float_srgb},
        {"readback", scene_readback}, {"feedback", scene_feedback}, {"glsl3-more", scene_glsl3_more},
        /* tex3d */
        {"array", scene_array}, {"volume", scene_volume},
        /* feedback */
        {"layer", scene_layer}, {"copy-layer", scene_copy_layer},
        /* glsl4 */
        {"flat", scene_flat}, {"int-switch", scene_int_switch},
        /* texfn */
        {"texfn", scene_texfn},
        /* contexts */
        {"contexts", scene_contexts}};
    if (argc != 2) die("usage: probe3 SCENE");
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        if (strcmp(argv[1], scenes[i].name) == 0) {
            setup();
            scenes[i].draw();
            return 0;
        }
    }
    die("unknown scene");
}
